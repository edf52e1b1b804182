#pragma once
// A point against a box in SIMD lanes, in the box's frame (centered, axis-aligned): how far outside
// it is, squared, and how deep inside. A sphere of radius r is clear of the box where out2 >= r^2.
#include "dmgplace/runtime/system/lanes.hpp"

namespace dmgplace::runtime::kernels {

struct LaneGap {
  lanes::F out2;    // squared distance from the shape's outside (0 inside)
  lanes::F inside;  // the largest face offset where that is negative (the depth, negated; 0 outside)
};

// half: the box's half extents.
inline __attribute__((always_inline)) LaneGap box_gap(lanes::F px, lanes::F py, lanes::F pz, const float* half) {
  const lanes::F ox = lanes::abs(px) - lanes::splatf(half[0]), oy = lanes::abs(py) - lanes::splatf(half[1]),
                 oz = lanes::abs(pz) - lanes::splatf(half[2]);
  const lanes::F cx = lanes::max0(ox), cy = lanes::max0(oy), cz = lanes::max0(oz);
  return {cx * cx + cy * cy + cz * cz, lanes::min(lanes::max(ox, lanes::max(oy, oz)), lanes::F{})};
}

}  // namespace dmgplace::runtime::kernels
