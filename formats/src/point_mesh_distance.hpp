#pragma once
// Distance from a point to a triangle mesh, for validating stored surface points (private to
// dmgplace_formats). Brute force over triangles with a bounding-box early-out: validation runs
// once per file, and the formats library must not depend on a BVH library.
#include <Eigen/Core>
#include <algorithm>
#include <limits>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::formats::detail {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
inline Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                           const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// True when p lies within `tol` of the mesh surface. Indices must already be checked.
inline bool near_surface(const TriMesh& m, const Eigen::Vector3d& p, double tol) {
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = m.vertices.row(m.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = m.vertices.row(m.triangles(t, 2)).transpose();
    const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c).array() - tol;
    const Eigen::Vector3d hi = a.cwiseMax(b).cwiseMax(c).array() + tol;
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    if ((closest_on_triangle(p, a, b, c) - p).norm() <= tol) return true;
  }
  return false;
}

}  // namespace dmgplace::formats::detail
