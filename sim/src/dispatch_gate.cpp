#include "dispatch_gate.h"

#include "bindings.h"
#include "gpu_types.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

namespace sphfx::sim {

DispatchGate::DispatchGate(uint32_t particles) {
  add(particles, kSimWorkGroup);  // kFinalEntry
  add(particles, kSimWorkGroup);  // kParticleEntry
}

uint32_t DispatchGate::add(uint32_t invocations, uint32_t localSize) {
  const uint32_t entry = entries();
  live_.insert(live_.end(), {(invocations + localSize - 1) / localSize, 1, 1});
  return entry;
}

void DispatchGate::arm() {
  // [args | live values]: the time step pass restores nothing, it only closes; arming reopens.
  std::vector<uint32_t> words(live_);
  words.insert(words.end(), live_.begin(), live_.end());
  if (buffer_.size() != words.size() * 4) buffer_.resize(words.size() * 4);
  buffer_.upload(words.data(), words.size() * 4);
}

void DispatchGate::bind() const {
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buffer_.id());
  buffer_.bindStorage(SPHFX_SSBO_SIM_DISPATCH);
}

void DispatchGate::dispatch(uint32_t entry, const char* label) const {
  if (live_[entry * 3] == 0) return;  // nothing to do at all (e.g. no items)
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buffer_.id());
  glDispatchComputeIndirect(GLintptr(entry) * 12);
  glCheck(label);
}

void storageBarrier() {
  // Texel fetches too: neighbour loops read the buffers through buffer textures (sph_textures.glsl).
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
}

}  // namespace sphfx::sim
