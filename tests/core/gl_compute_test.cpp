// Compute smoke test on a real headless context: dispatch, SSBO round trip, atomics, a uniform block
// and the shared include, against a CPU reference. ctest runs it once per backend (SPHFX_GL).
#include <gtest/gtest.h>

#include <cstdlib>

#include "sphfx/core/gl_context.h"
#include "sphfx/core/selftest.h"

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
