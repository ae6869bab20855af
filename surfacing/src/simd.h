#pragma once
// The instruction sets the surfacing stage's hot loops are built for (internal).

namespace sphfx::surfacing {

/// Auto picks AVX2 where the CPU has it. Every loop built twice gives bit-identical results on both
/// (the same per-lane IEEE operations, no FMA contraction in ISO C++ mode); the choice exists for the
/// tests that check that.
enum class SimdIsa { Auto, Baseline, Avx2 };

/// Whether this CPU can run `isa`.
inline bool simdSupported(SimdIsa isa) {
  return isa != SimdIsa::Avx2 || __builtin_cpu_supports("avx2");
}

/// Whether a loop built for `isa` should take its AVX2 build.
inline bool useAvx2(SimdIsa isa) {
  return isa == SimdIsa::Avx2 || (isa == SimdIsa::Auto && simdSupported(SimdIsa::Avx2));
}

}  // namespace sphfx::surfacing
