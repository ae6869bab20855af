// Compute smoke test on a real headless context: dispatch, SSBO round trip, atomics, a uniform block
// and the shared include, against a CPU reference. ctest runs it once per backend (SPHFX_GL).
#include <gtest/gtest.h>

#include <cstdlib>

#include <bit>
#include <cstring>
#include <vector>

#include "bindings.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/selftest.h"
#include "sphfx/gpu/shader_program.h"

using namespace sphfx;

GLBackend backendFromEnv() {
  const char* name = std::getenv("SPHFX_GL");
  return parseGLBackend(name ? name : "auto");
}

TEST(GLCompute, ContextIsCoreAndCapable) {
  auto ctx = GLContext::create({backendFromEnv(), true});
  const GLInfo& i = ctx->info();
  EXPECT_GE(i.major * 10 + i.minor, 43) << i.version;
  EXPECT_GE(i.maxComputeWorkGroupInvocations, 64);
  EXPECT_GE(i.maxShaderStorageBindings, 8);
  if (std::getenv("SPHFX_GL")) {
    EXPECT_EQ(toString(ctx->backend()), std::getenv("SPHFX_GL"));
  }
}

TEST(GLCompute, DispatchMatchesCpu) {
  auto ctx = GLContext::create({backendFromEnv(), true});
  std::vector<float> input(1000);  // 1000 is not a multiple of the 64-wide group: the tail is guarded
  for (size_t i = 0; i < input.size(); ++i) input[i] = 1.0f + float(i);
  const ComputeSelfTestResult r = runComputeSelfTest(input, 2.0f, 0.5f);
  uint32_t cells = 0;
  for (size_t i = 0; i < input.size(); ++i) {
    ASSERT_FLOAT_EQ(r.data[i], input[i] * 2.0f + 0.5f) << i;
    // sphfxCellIndex of cell (i%4, (i/4)%4, (i/16)%4) in a 4^3 grid, x fastest
    cells += uint32_t((i % 4) + 4 * ((i / 4) % 4) + 16 * ((i / 16) % 4));
  }
  EXPECT_EQ(r.invocations, 1000u);
  EXPECT_FLOAT_EQ(r.maxValue, 1000.0f * 2.0f + 0.5f);
  EXPECT_EQ(r.cellIndexSum, cells);
  EXPECT_EQ(verifyComputeSelfTest(), "");
}

TEST(GLCompute, EmptyDispatchIsHarmless) {
  auto ctx = GLContext::create({backendFromEnv(), true});
  const ComputeSelfTestResult r = runComputeSelfTest({}, 1, 1);
  EXPECT_TRUE(r.data.empty());
  EXPECT_EQ(r.invocations, 0u);
}

// Texels fetched through the buffer-texture views (the simulation's neighbour loops read this way) are
// the uploaded bits, and a view follows its buffer when the buffer is resized.
namespace {

struct FetchedTexels {
  std::vector<float> floats;
  std::vector<uint32_t> words;
};

FetchedTexels fetchThroughViews(const GpuBuffer& floats, const GpuBuffer& words, uint32_t count) {
  const ShaderProgram p = ShaderProgram::compute(gpuShaderTable(), "selftest_texture.comp");
  GpuBuffer floatsOut(size_t(count) * 16), wordsOut(size_t(count) * 4);
  floats.bindTexture(SPHFX_TEX_SELFTEST_FLOATS, GL_RGBA32F);
  words.bindTexture(SPHFX_TEX_SELFTEST_WORDS, GL_R32UI);
  floatsOut.bindStorage(SPHFX_SSBO_SELFTEST_FLOATS_OUT);
  wordsOut.bindStorage(SPHFX_SSBO_SELFTEST_WORDS_OUT);
  p.use();
  glProgramUniform1ui(p.id(), p.uniform("uCount"), count);
  glDispatchCompute((count + 63) / 64, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  return {floatsOut.downloadVector<float>(size_t(count) * 4), wordsOut.downloadVector<uint32_t>(count)};
}

std::vector<float> texelFloats(uint32_t count, float scale) {
  std::vector<float> v(size_t(count) * 4);
  for (size_t k = 0; k < v.size(); ++k) v[k] = scale * (float(k) - 7.25f) * (k % 3 ? 1.0f : -1e-3f);
  // Integers as float bits (denormals), as the DFSPH list entries and positions carry indices and ids
  // in w: a fetch must return the bits, not flush them to zero.
  for (size_t k = 3; k < v.size(); k += 4) v[k] = std::bit_cast<float>(uint32_t(k * 977u));
  return v;
}

std::vector<uint32_t> texelWords(uint32_t count, uint32_t salt) {
  std::vector<uint32_t> v(count);
  for (uint32_t k = 0; k < count; ++k) v[k] = (k * 2654435761u) ^ salt;
  return v;
}

void expectSameBits(const std::vector<float>& a, const std::vector<float>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k)
    ASSERT_EQ(std::bit_cast<uint32_t>(a[k]), std::bit_cast<uint32_t>(b[k])) << "component " << k;
}

}  // namespace

TEST(GLCompute, BufferTextureViewsFetchTheStoredBitsAndFollowResize) {
  auto ctx = GLContext::create({backendFromEnv(), true});
  GpuBuffer floats, words;
  for (uint32_t count : {100u, 1000u}) {  // the second pass resizes both buffers under their views
    const std::vector<float> f = texelFloats(count, float(count));
    const std::vector<uint32_t> w = texelWords(count, count);
    floats.uploadVector(f);
    words.uploadVector(w);
    const FetchedTexels got = fetchThroughViews(floats, words, count);
    expectSameBits(got.floats, f);
    EXPECT_EQ(got.words, w);
  }
  EXPECT_THROW(floats.bindTexture(SPHFX_TEX_SELFTEST_FLOATS, GL_RGB8), GLError);
}
