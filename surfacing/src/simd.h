#pragma once
// The instruction sets the surfacing stage's hot loops are built for (internal).

namespace sphfx::surfacing {

/// Auto picks AVX2 where the CPU has it. Every loop built twice gives bit-identical results on both
/// (the same per-lane IEEE operations, no FMA contraction in ISO C++ mode); the choice exists for the
/// tests that check that.
enum class SimdIsa { Auto, Baseline, Avx2 };

// The attribute of the AVX2 builds. Elsewhere than x86 they compile as plain copies, never chosen.
#if defined(__x86_64__) || defined(__i386__)
#define SPHFX_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define SPHFX_TARGET_AVX2
#endif

/// Whether this CPU can run `isa`.
inline bool simdSupported(SimdIsa isa) {
#if defined(__x86_64__) || defined(__i386__)
  return isa != SimdIsa::Avx2 || __builtin_cpu_supports("avx2");
#else
  return isa != SimdIsa::Avx2;
#endif
}

/// Whether a loop built for `isa` should take its AVX2 build.
inline bool useAvx2(SimdIsa isa) {
  return isa == SimdIsa::Avx2 || (isa == SimdIsa::Auto && simdSupported(SimdIsa::Avx2));
}

}  // namespace sphfx::surfacing
