#pragma once
// Distance from a point to a triangle mesh, for validating stored surface points (private to
// dmgplace_formats). Brute force over triangles with a bounding-box early-out: validation runs
// once per file, and the formats library must not depend on a BVH library.
#include <Eigen/Core>
#include <algorithm>
#include <limits>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/triangle_distance.hpp"

namespace dmgplace::formats::detail {

// True when p lies within `tol` of the mesh surface. Indices must already be checked.
inline bool near_surface(const TriMesh& m, const Eigen::Vector3d& p, double tol) {
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = m.vertices.row(m.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = m.vertices.row(m.triangles(t, 2)).transpose();
    const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c).array() - tol;
    const Eigen::Vector3d hi = a.cwiseMax(b).cwiseMax(c).array() + tol;
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    if ((closest_point_on_triangle(p, a, b, c) - p).norm() <= tol) return true;
  }
  return false;
}

}  // namespace dmgplace::formats::detail
