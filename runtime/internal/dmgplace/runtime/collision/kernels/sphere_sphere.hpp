#pragma once
// Sphere against sphere in SIMD lanes: the self-pair and body-pair test of the lane check.
#include "dmgplace/runtime/collision/kernels/lane_points.hpp"

namespace dmgplace::runtime::kernels {

// Lanes where spheres a and b (centers in lanes) are closer than `reach` (sum of radii + padding +
// margin), as a mask: a caller testing many sphere pairs ORs them and takes the bits once (the
// bits cost more than the test).
inline __attribute__((always_inline)) lanes::MF overlaps(const LaneXyz& a, const LaneXyz& b, lanes::F reach2) {
  const lanes::F dx = lanes::load(a.x) - lanes::load(b.x), dy = lanes::load(a.y) - lanes::load(b.y),
                 dz = lanes::load(a.z) - lanes::load(b.z);
  return dx * dx + dy * dy + dz * dz < reach2;
}
inline __attribute__((always_inline)) lanes::MF overlaps(const LaneXyz& a, const LaneXyz& b, float reach) {
  return overlaps(a, b, lanes::splatf(reach * reach));
}

}  // namespace dmgplace::runtime::kernels
