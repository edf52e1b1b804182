#pragma once
// A capsule (a segment and a radius) holding a set of spheres. A long link's spheres fit one far
// tighter than their bounding sphere (the Panda's forearm: 0.098 m against 0.200 m), so a test
// against it settles body pairs that the bounding spheres leave near (SphereFieldChecker's batch).
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "dmgplace/runtime/system/lanes.hpp"

namespace dmgplace::runtime {

struct Capsule {
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  double radius = 0;
};

// The capsule along the centres' principal axis, its ends at their extreme projections on it, its
// radius reaching every sphere's far side (rounded up). Nothing for fewer than two distinct centres
// or a non-finite input.
std::optional<Capsule> bounding_capsule(const std::vector<Eigen::Vector3d>& centers, const std::vector<double>& radii);

// Distance from p to the segment [from, to].
double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& from, const Eigen::Vector3d& to);

namespace lanes {

// Relative rounding of near_segment's float distance: it can exceed the exact one by at most
// kSegmentRounding x 2^-24 x (|p - from| + |d|) (the point's offset, the nearest parameter's
// product and quotient, the nearest point and the squared sum each add a few units).
constexpr double kSegmentRounding = 16;

// Lanes where point p is nearer than sqrt(reach2) to the segment from + t d, t in [0, 1], up to
// the rounding above (inv_len2 = 1 / |d|^2). Any t in [0, 1] names a point of the segment, so a
// rounded t can only make the distance longer, by at most its error times |d|. NaN: near.
DMGPLACE_LANES_INLINE MF near_segment(F px, F py, F pz, F fx, F fy, F fz, F dx, F dy, F dz, F inv_len2, F reach2) {
  const F wx = px - fx, wy = py - fy, wz = pz - fz;
  const F t = min(max0((wx * dx + wy * dy + wz * dz) * inv_len2), splatf(1.0f));
  const F ex = wx - t * dx, ey = wy - t * dy, ez = wz - t * dz;
  return ~(ex * ex + ey * ey + ez * ez >= reach2);
}

}  // namespace lanes
}  // namespace dmgplace::runtime
