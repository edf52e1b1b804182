#pragma once
// Generalised winding number of a triangle mesh at a point: ~1 inside a closed outward mesh, ~0
// outside, robust to small gaps. Shared by the sphere cover (tools) and the spheres' inner balls
// (runtime).
#include <Eigen/Core>
#include <cmath>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::formats {

// Sum over the triangles of their solid angles at p (Van Oosterom and Strackee: each is twice the
// argument of den + i num), over 4 pi. The arguments are added by multiplying the complex numbers
// and counting the turns the product makes across the negative real axis, so only the last one
// takes an atan2: a sphere cover asks this at thousands of points per link.
inline double winding_number(const TriMesh& m, const Eigen::Vector3d& p) {
  double re = 1, im = 0;  // the product so far, rescaled to keep it in range
  long turns = 0;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)).transpose() - p;
    const Eigen::Vector3d b = m.vertices.row(m.triangles(t, 1)).transpose() - p;
    const Eigen::Vector3d c = m.vertices.row(m.triangles(t, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    if (num == 0 && den >= 0) continue;  // an argument of 0 (or p on the triangle's corner or edge)
    const double r = re * den - im * num, i = re * num + im * den;
    // Arguments lie in (-pi, pi]; the upper half-plane holds [0, pi]. Turning counter-clockwise
    // (num > 0, or by pi) from it into the lower one, or by pi from pi onto the positive axis,
    // passes -1; so does turning clockwise from the lower half-plane into the upper one.
    if (num >= 0) {
      if (im >= 0 && (i < 0 || (i == 0 && r > 0 && re < 0))) ++turns;
    } else if (im < 0 && i >= 0) {
      --turns;
    }
    const double scale = 1 / std::max(std::abs(r), std::abs(i));
    re = r * scale;
    im = i == 0 ? 0.0 : i * scale;  // no -0: atan2 would read it as the lower half-plane
  }
  return (std::atan2(im, re) + 2 * M_PI * double(turns)) / (2 * M_PI);
}

}  // namespace dmgplace::formats
