#pragma once
/// @file dispatch_gate.h
/// @brief Indirect dispatches that the GPU itself can switch off: the time step pass empties them once a
/// frame is reached, so the CPU queues substeps in batches without reading anything back per substep.

#include <cstdint>
#include <vector>

#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::sim {

class DispatchGate {
 public:
  /// Entry kFinalEntry is the integration of `particles`: the only dispatch the last substep of a
  /// frame keeps after the time step pass; kParticleEntry is every other per-particle pass. Needs a
  /// current context.
  explicit DispatchGate(uint32_t particles);

  static constexpr uint32_t kFinalEntry = 0;
  static constexpr uint32_t kParticleEntry = 1;

  /// Registers a dispatch of `invocations` threads in groups of `localSize`; returns its entry. Call
  /// before arm().
  uint32_t add(uint32_t invocations, uint32_t localSize);
  /// Opens every entry (uploads the live arguments). Done at every frame start.
  void arm();
  /// Binds the argument buffer (indirect dispatch and, for the time step pass, shader storage).
  void bind() const;
  /// glDispatchComputeIndirect of `entry` with `program` in use. @throws GLError in debug mode.
  void dispatch(uint32_t entry, const char* label) const;
  uint32_t entries() const { return uint32_t(live_.size() / 3); }

 private:
  std::vector<uint32_t> live_;
  GpuBuffer buffer_;
};

/// glMemoryBarrier for shader storage written by one pass and read by the next (as storage or through
/// a buffer texture view, sph_textures.glsl).
void storageBarrier();

}  // namespace sphfx::sim
