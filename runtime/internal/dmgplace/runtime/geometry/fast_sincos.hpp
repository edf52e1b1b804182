#pragma once
// sin and cos of one angle together, for forward kinematics: one reduction to [-pi/4, pi/4] and two
// short polynomials (Cephes' coefficients), a few times faster than libm's sincos and within
// 2e-16 of it for the joint ranges of real arms (|x| < 1e5; beyond, libm).
#include <cmath>

#include "dmgplace/runtime/system/lanes.hpp"

namespace dmgplace::runtime {

namespace sincos_reduction {
// x = j * pi/2 + y, pi/2 split in two so j * pi/2 is exact for the j used here (fdlibm's split).
constexpr double kTwoOverPi = 6.36619772367581382433e-01;
constexpr double kPio2Hi = 1.57079632673412561417e+00, kPio2Lo = 6.07710050650619224932e-11;
// Rounded to the nearest integer (ties to even, as nearbyint) by adding and removing 1.5 * 2^52,
// exact below 2^51: no libm call in a scalar build, one add and one subtract per lane in a loop.
constexpr double kRound = 0x1.8p52;
}  // namespace sincos_reduction

// The core for |x| < 1e5, without branches (the quadrant picked by selects), so a loop over
// lanes of it vectorises (Kinematics::link_pose_lanes).
inline __attribute__((always_inline)) void fast_sincos_core(double x, double& s, double& c) {
  using namespace sincos_reduction;
  const double j = (x * kTwoOverPi + kRound) - kRound;
  const double y = (x - j * kPio2Hi) - j * kPio2Lo;
  const double z = y * y;
  const double sy = y + y * z *
                            (-1.66666666666666307295e-1 +
                             z * (8.33333333332211858878e-3 +
                                  z * (-1.98412698295895385996e-4 +
                                       z * (2.75573136213857245213e-6 +
                                            z * (-2.50507477628578072866e-8 + z * 1.58962301576546568060e-10)))));
  const double cy = 1.0 - 0.5 * z +
                    z * z *
                        (4.16666666666665929218e-2 +
                         z * (-1.38888888888730564116e-3 +
                              z * (2.48015872888517045348e-5 +
                                   z * (-2.75573141792967388112e-7 +
                                        z * (2.08757008419747316778e-9 + z * -1.13585365213876817300e-11)))));
  const int q = static_cast<int>(j) & 3;  // quadrant: (s, c) = (sy, cy), (cy, -sy), (-sy, -cy), (-cy, sy)
  const double ss = (q & 1) ? cy : sy, cc = (q & 1) ? sy : cy;
  s = (q & 2) ? -ss : ss;
  c = ((q + 1) & 2) ? -cc : cc;
}

// sin and cos of n angles (x[k] into s[k], c[k]) in SIMD lanes: AVX2 where the CPU has it (no
// FMA, so every lane rounds as fast_sincos does), else the portable build. Kinematics::link_poses
// asks for all its joints at once.
void fast_sincos_many(const double* x, int n, double* s, double* c);

// fast_sincos_f8's worst error, in units of 2^-24 (a float's unit roundoff), for sin and cos alike:
// its polynomials in floats are within 0.79 (sin) and 1.25 (cos) of the true value of every float
// in [-pi/4, pi/4] (all of them measured, with and without fused multiply-adds), and rounding the
// reduced angle to a float moves it by at most pi/4 of a unit (both functions have slope <= 1):
// under 2.1 in all; 2.5 leaves room. Kinematics::bound_float_error counts it per revolute joint.
constexpr double kSincosF8Error = 2.5;

inline void fast_sincos(double x, double& s, double& c) {
  if (!(std::abs(x) < 1e5)) {  // also NaN
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  fast_sincos_core(x, s, c);
}

// sin and cos of 8 angles (doubles, |x| < 1e5) in floats, for the float lane kinematics: the
// reduction as fast_sincos_core's, in doubles (exact j * pi/2), the reduced angle rounded to a float,
// then Cephes' sinf/cosf polynomials on all 8 lanes of one float vector, about half the work of
// the double core's two vectors and degree-6 polynomials. Within kSincosF8Error of the truth.
DMGPLACE_LANES_INLINE void fast_sincos_f8(const double* x, float* s, float* c) {
  using lanes::D;
  using lanes::F;
  using lanes::MF;
  using lanes::splat;
  using lanes::splatf;
  typedef float F4 __attribute__((vector_size(4 * sizeof(float))));
  typedef int I4 __attribute__((vector_size(4 * sizeof(int))));
  using namespace sincos_reduction;
  F4 y4[2];
  I4 q4[2];
  for (int h = 0; h < 2; ++h) {
    const D v = lanes::load(x + 4 * h);
    const D j = (v * splat(kTwoOverPi) + splat(kRound)) - splat(kRound);
    y4[h] = __builtin_convertvector((v - j * splat(kPio2Hi)) - j * splat(kPio2Lo), F4);
    q4[h] = __builtin_convertvector(j, I4);  // j is a whole number: exact
  }
  const F y = __builtin_shufflevector(y4[0], y4[1], 0, 1, 2, 3, 4, 5, 6, 7);
  const MF q = __builtin_shufflevector(q4[0], q4[1], 0, 1, 2, 3, 4, 5, 6, 7);
  const F z = y * y;
  const F sy = y + y * z * (splatf(-1.6666654611e-1f) + z * (splatf(8.3321608736e-3f) + z * splatf(-1.9515295891e-4f)));
  const F cy =
      splatf(1.0f) - splatf(0.5f) * z +
      z * z *
          (splatf(4.166664568298827e-2f) + z * (splatf(-1.388731625493765e-3f) + z * splatf(2.443315711809948e-5f)));
  // The quadrant, as fast_sincos_core: (s, c) = (sy, cy), (cy, -sy), (-sy, -cy), (-cy, sy).
  const MF one = MF{} + 1, two = one + one;
  const MF odd = (q & one) != MF{};
  const F ss = odd ? cy : sy, cc = odd ? sy : cy;
  lanes::store(s, (q & two) != MF{} ? -ss : ss);
  lanes::store(c, ((q + one) & two) != MF{} ? -cc : cc);
}

}  // namespace dmgplace::runtime
