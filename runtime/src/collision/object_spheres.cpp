#include "dmgplace/runtime/collision/object_spheres.hpp"

#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/triangle_distance.hpp"

namespace dmgplace::runtime {
namespace {
Eigen::Vector3d vertex(const TriMesh& m, int t, int k) { return m.vertices.row(m.triangles(t, k)).transpose(); }

// Does the ray p + s * e_axis (s > 0) cross triangle t? (Moller-Trumbore on an axis direction.)
bool crosses(const TriMesh& m, int t, const Eigen::Vector3d& p, int axis) {
  const Eigen::Vector3d a = vertex(m, t, 0), b = vertex(m, t, 1), c = vertex(m, t, 2);
  const Eigen::Vector3d d = Eigen::Vector3d::Unit(axis);
  const Eigen::Vector3d e1 = b - a, e2 = c - a, h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-15) return false;
  const Eigen::Vector3d s = p - a;
  const double u = s.dot(h) / det;
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = d.dot(qv) / det;
  if (v < 0 || u + v > 1) return false;
  return e2.dot(qv) / det > 0;
}
}  // namespace

bool inside_mesh(const TriMesh& m, const Eigen::Vector3d& p) {
  int votes = 0;
  for (int axis = 0; axis < 3; ++axis) {
    int hits = 0;
    for (int t = 0; t < m.triangles.rows(); ++t) hits += crosses(m, t, p, axis);
    votes += hits % 2;
  }
  return votes >= 2;
}

SphereSet cover_object(const TriMesh& m, int cells_per_axis) {
  if (m.empty()) throw Error("object", "mesh", "empty mesh: nothing to cover with spheres");
  if (!m.vertices.allFinite()) throw Error("object", "mesh", "vertex coordinates are not finite");
  const Eigen::Vector3d lo = m.vertices.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = m.vertices.colwise().maxCoeff().transpose();
  const double cell = std::max((hi - lo).maxCoeff() / std::max(1, cells_per_axis), 1e-4);
  const double radius = std::sqrt(3.0) / 2.0 * cell;
  Eigen::Array3i n = ((hi - lo) / cell).array().ceil().cast<int>().max(1);
  const Eigen::Vector3d start = 0.5 * (lo + hi) - 0.5 * cell * n.cast<double>().matrix();
  SphereSet out;
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const Eigen::Vector3d c = start + cell * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
        double d2 = std::numeric_limits<double>::infinity();
        for (int t = 0; t < m.triangles.rows() && d2 > radius * radius; ++t)
          d2 = std::min(d2, (closest_point_on_triangle(c, vertex(m, t, 0), vertex(m, t, 1), vertex(m, t, 2)) - c).squaredNorm());
        // A cube touches the surface when the surface comes within its circumscribed sphere.
        if (d2 <= radius * radius || inside_mesh(m, c)) {
          out.centers.push_back(c);
          out.radii.push_back(radius);
        }
      }
  return out;
}

}  // namespace dmgplace::runtime
