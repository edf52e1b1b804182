#pragma once
// Four doubles (D) or eight floats (F) as one GCC/Clang vector (vector_size 32): a function
// compiled for AVX2 (simd_dispatch.hpp) runs each operation as one instruction, the portable build
// as two SSE2 ones. Lane forward kinematics in doubles takes its 8 configurations as two D
// halves; in floats, as the lane sphere check runs it, one F. Written this way they
// vectorise for certain, where plain loops depend on the auto-vectoriser's cost model; operands
// are whole vectors (splat), since a scalar operand makes GCC compare lane by lane. Comparisons
// give a mask: -1 in true lanes, 0 elsewhere. The files using sqrt() are built with
// -fno-math-errno, so it is one instruction too.
#include <cstdint>
#include <cstring>
#include <type_traits>

#define DMGPLACE_LANES_INLINE inline __attribute__((always_inline))

// Every function here is inlined: no vector crosses a call, so GCC's notes about the vector ABI
// are moot (the build passes -Wno-psabi; a pragma does not reach them).

namespace dmgplace::runtime::lanes {

constexpr int W = 4;  // lanes per vector
typedef double D __attribute__((vector_size(W * sizeof(double))));
typedef long long M __attribute__((vector_size(W * sizeof(long long))));

DMGPLACE_LANES_INLINE D splat(double v) { return D{v, v, v, v}; }
// One vmovmskpd / vmovmskps for a whole mask. Not always_inline: inlined only into callers compiled
// for AVX (the SIMD dispatch's avx2 functions), where bits(m, true) asks for it.
inline __attribute__((target("avx"))) std::uint32_t movemask_avx(M m) {
  return std::uint32_t(__builtin_ia32_movmskpd256((D)m));
}
// Bit k set where lane k of the mask is true. `wide`: the caller is compiled for AVX, where the
// mask is one register and one instruction takes its sign bits. The portable build compares lane
// by lane (GCC lowers 256-bit vectors to scalars there), so its masks are built in general
// registers, where the masking and OR cost less than moving them back into vectors. The caller
// passes a constant; the branch folds away.
DMGPLACE_LANES_INLINE std::uint32_t bits(M m, bool wide = false) {
  if (wide) return movemask_avx(m);
  const M w = m & M{1, 2, 4, 8};
  return std::uint32_t(w[0] | w[1] | w[2] | w[3]);
}

// Eight lanes of floats, one register under AVX (two SSE ones in the portable build): the lane check
// sphere check, forward kinematics included, where single precision plus a rounding margin is enough
// and each operation then covers all 8 configurations.
constexpr int WF = 8;
typedef float F __attribute__((vector_size(WF * sizeof(float))));
typedef int MF __attribute__((vector_size(WF * sizeof(int))));

// One broadcast under AVX. These helpers are lowered before they are inlined into the AVX
// functions, and GCC 12 lowers F{v, ..., v} there as for SSE, a chain of inserts; a shuffle of a
// one-lane vector stays a broadcast. (The portable build then stores lane by lane.)
DMGPLACE_LANES_INLINE F splatf(float v) {
  typedef float F4 __attribute__((vector_size(4 * sizeof(float))));
  F4 x;
  x[0] = v;
  return __builtin_shufflevector(x, x, 0, 0, 0, 0, 0, 0, 0, 0);
}
// Two doubles: one SSE2 register, what a portable build runs natively (its 4-double D is split
// into pairs, comparisons lane by lane); PrimitiveObstacles::distance's portable path.
typedef double D2 __attribute__((vector_size(2 * sizeof(double))));

// The same operations for every kind of vector.
template <class V>
concept Vector = std::is_same_v<V, D> || std::is_same_v<V, F> || std::is_same_v<V, D2>;
template <class T>
using VectorOf = std::conditional_t<std::is_same_v<T, double>, D, F>;
template <class T>
requires Vector<VectorOf<T>> DMGPLACE_LANES_INLINE VectorOf<T> load(const T* p) {
  VectorOf<T> v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class T>
DMGPLACE_LANES_INLINE void store(T* p, VectorOf<T> v) {
  std::memcpy(p, &v, sizeof v);
}
template <Vector V>
DMGPLACE_LANES_INLINE V min(V a, V b) {
  return a < b ? a : b;
}
template <Vector V>
DMGPLACE_LANES_INLINE V max(V a, V b) {
  return a > b ? a : b;
}
template <Vector V>
DMGPLACE_LANES_INLINE V max0(V a) {
  return max(a, V{});
}
template <Vector V>
DMGPLACE_LANES_INLINE V abs(V a) {
  return max(a, -a);
}
template <Vector V>
DMGPLACE_LANES_INLINE V sqrt(V a) {
  V r;
  for (int k = 0; k < int(sizeof(V) / sizeof(a[0])); ++k) {
    if constexpr (std::is_same_v<V, F>) r[k] = __builtin_sqrtf(a[k]);
    else r[k] = __builtin_sqrt(a[k]);
  }
  return r;
}
// As bits(M) for eight float lanes.
inline __attribute__((target("avx"))) std::uint32_t movemask_avx(MF m) {
  return std::uint32_t(__builtin_ia32_movmskps256((F)m));
}
DMGPLACE_LANES_INLINE std::uint32_t bits(MF m, bool wide = false) {
  if (wide) return movemask_avx(m);
  const MF w = m & MF{1, 2, 4, 8, 16, 32, 64, 128};
  return std::uint32_t(w[0] | w[1] | w[2] | w[3] | w[4] | w[5] | w[6] | w[7]);
}

}  // namespace dmgplace::runtime::lanes
