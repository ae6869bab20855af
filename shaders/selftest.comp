// Compute self-test: SSBO read-modify-write, atomics, a uniform block and a shared include.
// Used by `sphfx info --selftest` and tests/core/gl_compute_test.cpp.
#include "selftest_layout.glsl"

layout(local_size_x = 64) in;

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= selftestCount) return;
  data[i] = data[i] * selftestScale + selftestOffset.x;
  atomicAdd(counters[0], 1u);                          // one per invocation
  atomicMax(counters[1], floatBitsToUint(data[i]));    // positive floats order as uints
  // The shared include: cell index of a 4x4x4 grid, summed over all invocations.
  ivec3 cell = ivec3(i % 4u, (i / 4u) % 4u, (i / 16u) % 4u);
  atomicAdd(counters[2], sphfxCellIndex(cell, ivec3(4)));
}
