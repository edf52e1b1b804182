#pragma once
// A capsule (a segment and a radius) holding a set of spheres. A long link's spheres fit one far
// tighter than their bounding sphere (the Panda's forearm: 0.098 m against 0.200 m), so a test
// against it settles body pairs that the bounding spheres leave near (SphereFieldChecker's lanes:
// collision/kernels/sphere_capsule.hpp).
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace dmgplace::runtime {

struct Capsule {
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  double radius = 0;
};

// The capsule along the centers' principal axis, its ends at their extreme projections on it, its
// radius reaching every sphere's far side (rounded up). Nothing for fewer than two distinct centers
// or a non-finite input.
std::optional<Capsule> bounding_capsule(const std::vector<Eigen::Vector3d>& centers, const std::vector<double>& radii);

// Distance from p to the segment [from, to].
double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& from, const Eigen::Vector3d& to);

}  // namespace dmgplace::runtime
