#include "dmgplace/runtime/grasp/held_grasp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dmgplace/formats/triangle_distance.hpp"

namespace dmgplace::runtime {
namespace {
Eigen::Vector3d vertex(const TriMesh& m, Eigen::Index t, int k) {
  return m.vertices.row(m.triangles(t, k)).transpose();
}

// Parameter t of the line o + t d crossing triangle abc (Moller-Trumbore, both directions).
std::optional<double> crossing(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-14) return std::nullopt;  // parallel to the triangle
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return std::nullopt;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = d.dot(qv) / det;
  if (v < 0 || u + v > 1) return std::nullopt;
  return e2.dot(qv) / det;
}
}  // namespace

double surface_distance(const TriMesh& m, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t)
    best = std::min(
        best, (formats::closest_point_on_triangle(p, vertex(m, t, 0), vertex(m, t, 1), vertex(m, t, 2)) - p).norm());
  return best;
}

std::optional<double> grasp_width(const TriMesh& m, const Eigen::Isometry3d& tcp) {
  const Eigen::Vector3d o = tcp.translation(), d = tcp.linear().col(1);
  double lo = 0, hi = 0;
  bool below = false, above = false;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const auto x = crossing(o, d, vertex(m, t, 0), vertex(m, t, 1), vertex(m, t, 2));
    if (!x) continue;
    if (*x <= 0) lo = std::min(lo, *x), below = true;
    if (*x >= 0) hi = std::max(hi, *x), above = true;
  }
  if (!below || !above) return std::nullopt;
  return hi - lo;
}

}  // namespace dmgplace::runtime
