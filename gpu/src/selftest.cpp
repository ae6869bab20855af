#include "sphfx/gpu/selftest.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/gpu_layout.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx {

ComputeSelfTestResult runComputeSelfTest(const std::vector<float>& input, float scale, float offset) {
  const ShaderProgram program = ShaderProgram::compute(gpuShaderTable(), "selftest.comp");
  SelfTestParams params{};
  params.scale = scale;
  params.count = uint32_t(input.size());
  params.offset[0] = offset;
  GpuBuffer uniforms(sizeof(params));
  uniforms.upload(&params, sizeof(params));
  GpuBuffer data(input.size() * sizeof(float));
  data.uploadVector(input);
  GpuBuffer counters(4 * sizeof(uint32_t));
  counters.fill(0);

  uniforms.bindUniform(SPHFX_UBO_SELFTEST);
  data.bindStorage(SPHFX_SSBO_SELFTEST_DATA);
  counters.bindStorage(SPHFX_SSBO_SELFTEST_COUNTERS);
  program.use();
  dispatchCompute1D(program, uint32_t(input.size()), "selftest.comp");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

  ComputeSelfTestResult r;
  r.data = data.downloadVector<float>(input.size());
  const auto c = counters.downloadVector<uint32_t>(4);
  r.invocations = c[0];
  r.maxValue = std::bit_cast<float>(c[1]);
  r.cellIndexSum = c[2];
  return r;
}

std::string verifyComputeSelfTest() {
  std::vector<float> input(1000);  // not a multiple of the 64-wide work group on purpose
  for (size_t i = 0; i < input.size(); ++i) input[i] = 0.5f + float(i % 97) * 0.25f;
  const float scale = 1.5f, offset = 2.0f;
  const ComputeSelfTestResult r = runComputeSelfTest(input, scale, offset);
  float expectedMax = 0;
  uint32_t expectedCells = 0;
  for (size_t i = 0; i < input.size(); ++i) {
    const float expected = input[i] * scale + offset;
    if (std::fabs(r.data[i] - expected) > 1e-5f * expected)
      return fmt::format("data[{}] = {}, expected {}", i, r.data[i], expected);
    expectedMax = std::max(expectedMax, expected);
    expectedCells += uint32_t(i % 4 + 4 * ((i / 4) % 4) + 16 * ((i / 16) % 4));
  }
  if (r.invocations != input.size())
    return fmt::format("{} invocations, expected {}", r.invocations, input.size());
  if (r.maxValue != expectedMax)
    return fmt::format("atomicMax gave {}, expected {}", r.maxValue, expectedMax);
  if (r.cellIndexSum != expectedCells)
    return fmt::format("cell index sum {}, expected {}", r.cellIndexSum, expectedCells);
  return {};
}

}  // namespace sphfx
