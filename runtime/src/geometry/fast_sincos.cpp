#include "dmgplace/runtime/geometry/fast_sincos.hpp"

#include <algorithm>

#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::runtime {
namespace {

constexpr int kBlock = 8;  // lanes per step: two AVX2 vectors of doubles, four SSE2 ones

// Whole blocks of fast_sincos_core, which the compiler turns into vector code (the core has no
// branch); the caller pads the tail.
inline __attribute__((always_inline)) void blocks(const double* x, int n, double* s, double* c) {
  for (int b = 0; b < n; b += kBlock)
    for (int k = b; k < b + kBlock; ++k) fast_sincos_core(x[k], s[k], c[k]);
}

__attribute__((target("avx2"))) void blocks_avx2(const double* x, int n, double* s, double* c) { blocks(x, n, s, c); }
void blocks_portable(const double* x, int n, double* s, double* c) { blocks(x, n, s, c); }

}  // namespace

void fast_sincos_many(const double* x, int n, double* s, double* c) {
  for (int first = 0; first < n; first += kBlock) {
    const int m = std::min(kBlock, n - first);
    bool wild = false;
    double in[kBlock], so[kBlock], co[kBlock];
    for (int k = 0; k < kBlock; ++k) {
      in[k] = k < m ? x[first + k] : 0.0;
      wild |= !(std::abs(in[k]) < 1e5);  // also NaN
    }
    if (wild) {
      for (int k = 0; k < m; ++k) fast_sincos(in[k], s[first + k], c[first + k]);
      continue;
    }
    if (simd_path() == SimdPath::Avx2) blocks_avx2(in, kBlock, so, co);
    else blocks_portable(in, kBlock, so, co);
    std::copy_n(so, m, s + first);
    std::copy_n(co, m, c + first);
  }
}

}  // namespace dmgplace::runtime
