#pragma once
// Points in SIMD lanes and the rigid transform that places them: the float kernels' common
// ground (one lane per configuration of a lane check, lanes.hpp). Inline only: no vector crosses a call.
#include <array>

#include "dmgplace/runtime/robot/kinematics_lanes.hpp"
#include "dmgplace/runtime/system/lanes.hpp"

namespace dmgplace::runtime {

// Points in every lane.
struct alignas(32) LaneXyz {
  float x[LinkPoseLanesD::kLanes], y[LinkPoseLanesD::kLanes], z[LinkPoseLanesD::kLanes];
};

namespace kernels {

// A link's pose in every lane (LinkPoseLanesF): rotation row-major, then the translation.
using LinkPose = std::array<LinkPoseLanesF::Lanes, 12>;

// A link's pose loaded into vectors once for all its spheres: the stores of their centers could
// alias the pose's arrays for all the compiler knows, so it would reload all 12 per sphere.
struct PoseLanes {
  lanes::F t[12];
  explicit PoseLanes(const LinkPose& T) {
    for (int e = 0; e < 12; ++e) t[e] = lanes::load(T[std::size_t(e)].data());
  }
};

// c = R p + t in every lane, p given in every lane.
inline __attribute__((always_inline)) void transform(const PoseLanes& T, lanes::F px, lanes::F py, lanes::F pz,
                                                     LaneXyz& c) {
  const lanes::F* t = T.t;
  lanes::store(c.x, t[0] * px + t[1] * py + t[2] * pz + t[9]);
  lanes::store(c.y, t[3] * px + t[4] * py + t[5] * pz + t[10]);
  lanes::store(c.z, t[6] * px + t[7] * py + t[8] * pz + t[11]);
}

// Lanes with every coordinate of p within `limit` (false for NaN): a rounding margin holds there.
inline __attribute__((always_inline)) lanes::MF within(const LaneXyz& p, float limit) {
  const lanes::F l = lanes::splatf(limit);
  return (lanes::abs(lanes::load(p.x)) <= l) & (lanes::abs(lanes::load(p.y)) <= l) &
         (lanes::abs(lanes::load(p.z)) <= l);
}

}  // namespace kernels
}  // namespace dmgplace::runtime
