#pragma once
// A point (a sphere's center) against a capsule's segment in SIMD lanes: the body-pair test that
// settles a long link's spheres against the other body's bounding sphere (the capsule is built
// around the link's spheres: geometry/capsule.hpp).
#include "dmgplace/runtime/system/lanes.hpp"

namespace dmgplace::runtime::kernels {

// Relative rounding of near_segment's float distance: it can exceed the exact one by at most
// kSegmentRounding x 2^-24 x (|p - from| + |d|) (the point's offset, the nearest parameter's
// product and quotient, the nearest point and the squared sum each add a few units).
constexpr double kSegmentRounding = 16;

// Lanes where point p is nearer than sqrt(reach2) to the segment from + t d, t in [0, 1], up to
// the rounding above (inv_len2 = 1 / |d|^2). Any t in [0, 1] names a point of the segment, so a
// rounded t can only make the distance longer, by at most its error times |d|. NaN: near.
inline __attribute__((always_inline)) lanes::MF near_segment(lanes::F px, lanes::F py, lanes::F pz, lanes::F fx,
                                                             lanes::F fy, lanes::F fz, lanes::F dx, lanes::F dy,
                                                             lanes::F dz, lanes::F inv_len2, lanes::F reach2) {
  using lanes::F;
  const F wx = px - fx, wy = py - fy, wz = pz - fz;
  const F t = lanes::min(lanes::max0((wx * dx + wy * dy + wz * dz) * inv_len2), lanes::splatf(1.0f));
  const F ex = wx - t * dx, ey = wy - t * dy, ez = wz - t * dz;
  return ~(ex * ex + ey * ey + ez * ez >= reach2);
}

}  // namespace dmgplace::runtime::kernels
