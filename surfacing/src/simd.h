#pragma once
// The instruction sets the surfacing stage's hot loops are built for, and their 8-float vector type
// (internal).
#include <cstring>

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

// Eight floats as one value (GCC/Clang vector extension): SIMD on any target, two SSE registers on
// baseline x86-64 and one in the AVX2 builds, where a plain 8-iteration loop stayed scalar. Every
// function taking or returning one is inlined, so the AVX calling convention GCC warns about
// (-Wpsabi) never applies.
#pragma GCC diagnostic ignored "-Wpsabi"
using Float8 = float __attribute__((vector_size(32)));

inline __attribute__((always_inline)) Float8 load8(const float* p) {
  Float8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline __attribute__((always_inline)) void store8(float* p, Float8 v) {
  std::memcpy(p, &v, sizeof v);
}

}  // namespace sphfx::surfacing
