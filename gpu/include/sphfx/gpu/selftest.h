#pragma once
/// @file selftest.h
/// @brief A small compute dispatch that exercises what every stage relies on: SSBO round trip, atomics,
/// a uniform block and the shared include. Used by `sphfx info --selftest` and the GL tests.

#include <cstdint>
#include <string>
#include <vector>

namespace sphfx {

struct ComputeSelfTestResult {
  std::vector<float> data;    ///< input[i] * scale + offset, computed on the GPU
  uint32_t invocations = 0;   ///< atomicAdd count
  float maxValue = 0;         ///< atomicMax over the results (positive inputs)
  uint32_t cellIndexSum = 0;  ///< sum of sphfxCellIndex() over invocations (common.glsl)
};

/// Runs shaders/selftest.comp on `input` in the current context. @throws GLError.
ComputeSelfTestResult runComputeSelfTest(const std::vector<float>& input, float scale, float offset);

/// Runs the self-test on a fixed input and compares with the CPU; returns an empty string on success,
/// else what differs.
std::string verifyComputeSelfTest();

}  // namespace sphfx
