// GLSL side of sphfx::SelfTestParams (core/include/sphfx/gpu/gpu_layout.h).
layout(std140, binding = SPHFX_UBO_SELFTEST) uniform SelfTestParams {
  float selftestScale;
  uint selftestCount;
  vec4 selftestOffset;
};
layout(std430, binding = SPHFX_SSBO_SELFTEST_DATA) buffer SelfTestData { float data[]; };
layout(std430, binding = SPHFX_SSBO_SELFTEST_COUNTERS) buffer SelfTestCounters { uint counters[]; };
