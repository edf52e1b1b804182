#pragma once
// Generalised winding number of a triangle mesh at a point: ~1 inside a closed outward mesh, ~0
// outside, robust to small gaps. Shared by the sphere cover (tools) and the spheres' inner balls
// (runtime).
#include <Eigen/Core>
#include <cmath>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::formats {

inline double winding_number(const TriMesh& m, const Eigen::Vector3d& p) {
  double total = 0;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)).transpose() - p;
    Eigen::Vector3d b = m.vertices.row(m.triangles(t, 1)).transpose() - p;
    Eigen::Vector3d c = m.vertices.row(m.triangles(t, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2 * std::atan2(num, den);
  }
  return total / (4 * M_PI);
}

}  // namespace dmgplace::formats
