#pragma once
// A point against a cylinder in SIMD lanes, in the cylinder's frame (centered, its axis z): how far
// outside it is, squared, and how deep inside (kernels::LaneGap). A sphere of radius r is clear of
// the cylinder where out2 >= r^2.
#include "dmgplace/runtime/collision/kernels/sphere_box.hpp"

namespace dmgplace::runtime::kernels {

inline __attribute__((always_inline)) LaneGap cylinder_gap(lanes::F px, lanes::F py, lanes::F pz, float radius,
                                                           float half_length) {
  const lanes::F orad = lanes::sqrt(px * px + py * py) - lanes::splatf(radius),
                 oz = lanes::abs(pz) - lanes::splatf(half_length);
  const lanes::F cr = lanes::max0(orad), cz = lanes::max0(oz);
  return {cr * cr + cz * cz, lanes::min(lanes::max(orad, oz), lanes::F{})};
}

}  // namespace dmgplace::runtime::kernels
