#pragma once
// Four lanes of doubles as one GCC/Clang vector (vector_size 32): a function compiled for AVX2
// (simd_dispatch.hpp) runs each operation as one instruction, the portable build as two SSE2 ones.
// The batch kernels take their 8 configurations as two such halves. Written this way they
// vectorise for certain, where plain loops depend on the auto-vectoriser's cost model; operands
// are whole vectors (splat), since a scalar operand makes GCC compare lane by lane. Comparisons
// give a mask: -1 in true lanes, 0 elsewhere. The files using sqrt() are built with
// -fno-math-errno, so it is one instruction too.
#include <cstdint>
#include <cstring>

#define DMGPLACE_LANES_INLINE inline __attribute__((always_inline))

// Every function here is inlined: no vector crosses a call, so GCC's notes about the vector ABI
// are moot (the build passes -Wno-psabi; a pragma does not reach them).

namespace dmgplace::runtime::lanes {

constexpr int W = 4;  // lanes per vector
typedef double D __attribute__((vector_size(W * sizeof(double))));
typedef long long M __attribute__((vector_size(W * sizeof(long long))));
typedef int I __attribute__((vector_size(W * sizeof(int))));

DMGPLACE_LANES_INLINE D splat(double v) { return D{v, v, v, v}; }
DMGPLACE_LANES_INLINE D load(const double* p) {
  D v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
DMGPLACE_LANES_INLINE void store(double* p, D v) { std::memcpy(p, &v, sizeof v); }
DMGPLACE_LANES_INLINE D min(D a, D b) { return a < b ? a : b; }
DMGPLACE_LANES_INLINE D max(D a, D b) { return a > b ? a : b; }
DMGPLACE_LANES_INLINE D max0(D a) { return max(a, D{}); }
DMGPLACE_LANES_INLINE D abs(D a) { return max(a, -a); }
DMGPLACE_LANES_INLINE D sqrt(D a) {
  D r;
  for (int k = 0; k < W; ++k) r[k] = __builtin_sqrt(a[k]);
  return r;
}
// Truncation towards zero (vcvttpd2dq) and back.
DMGPLACE_LANES_INLINE I to_int(D a) { return __builtin_convertvector(a, I); }
DMGPLACE_LANES_INLINE D to_double(I a) { return __builtin_convertvector(a, D); }
// Bit k set where lane k of the mask is true. `wide`: the caller is compiled for AVX, where the
// mask is one register and SSE2's movmskpd on each half takes 4 instructions (the masking and OR
// took 10). The portable build compares lane by lane (GCC lowers 256-bit vectors to scalars
// there), so its masks are built in general registers, where the masking and OR cost less than
// moving them back into vectors. The caller passes a constant; the branch folds away.
DMGPLACE_LANES_INLINE std::uint32_t bits(M m, bool wide = false) {
#if defined(__SSE2__)
  if (wide) {
    typedef double H __attribute__((vector_size(16)));
    H lo, hi;
    std::memcpy(&lo, &m, sizeof lo);
    std::memcpy(&hi, reinterpret_cast<const char*>(&m) + sizeof lo, sizeof hi);
    return std::uint32_t(__builtin_ia32_movmskpd(lo)) | std::uint32_t(__builtin_ia32_movmskpd(hi)) << 2;
  }
#endif
  const M w = m & M{1, 2, 4, 8};
  return std::uint32_t(w[0] | w[1] | w[2] | w[3]);
}

}  // namespace dmgplace::runtime::lanes
