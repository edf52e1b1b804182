#pragma once
// sin and cos of one angle together, for forward kinematics: one reduction to [-pi/4, pi/4] and two
// short polynomials (Cephes' coefficients), a few times faster than libm's sincos and within
// 2e-16 of it for the joint ranges of real arms (|x| < 1e5; beyond, libm).
#include <cmath>

namespace dmgplace::runtime {

// The core for |x| < 1e5, without branches (the quadrant picked by selects), so a loop over
// lanes of it vectorises (Kinematics::link_poses_batch).
inline __attribute__((always_inline)) void fast_sincos_core(double x, double& s, double& c) {
  // x = j * pi/2 + y, pi/2 split in two so j * pi/2 is exact for the j used here (fdlibm's split).
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPio2Hi = 1.57079632673412561417e+00, kPio2Lo = 6.07710050650619224932e-11;
  // Rounded to the nearest integer (ties to even, as nearbyint) by adding and removing 1.5 * 2^52,
  // exact below 2^51: no libm call in a scalar build, one add and one subtract per lane in a loop.
  constexpr double kRound = 0x1.8p52;
  const double j = (x * kTwoOverPi + kRound) - kRound;
  const double y = (x - j * kPio2Hi) - j * kPio2Lo;
  const double z = y * y;
  const double sy = y + y * z * (-1.66666666666666307295e-1 +
                                 z * (8.33333333332211858878e-3 +
                                      z * (-1.98412698295895385996e-4 +
                                           z * (2.75573136213857245213e-6 +
                                                z * (-2.50507477628578072866e-8 + z * 1.58962301576546568060e-10)))));
  const double cy = 1.0 - 0.5 * z + z * z * (4.16666666666665929218e-2 +
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

inline void fast_sincos(double x, double& s, double& c) {
  if (!(std::abs(x) < 1e5)) {  // also NaN
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  fast_sincos_core(x, s, c);
}

}  // namespace dmgplace::runtime
