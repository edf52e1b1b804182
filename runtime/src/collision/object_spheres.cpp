#include "dmgplace/runtime/collision/object_spheres.hpp"

#include <algorithm>
#include <cmath>
#include <array>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/triangle_distance.hpp"

namespace dmgplace::runtime {
namespace {
Eigen::Vector3d vertex(const TriMesh& m, int t, int k) { return m.vertices.row(m.triangles(t, k)).transpose(); }

// Does the line through p along e_axis pass through triangle t? (Moller-Trumbore's u, v part on
// an axis direction: h = e_axis x e2 has no component along the axis, so u and v are the same for
// every origin on the line.)
bool on_line(const TriMesh& m, int t, const Eigen::Vector3d& p, int axis, double* det_out = nullptr,
             Eigen::Vector3d* qv_out = nullptr) {
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
  if (det_out) *det_out = det, *qv_out = qv;
  return true;
}

// Does the ray p + s * e_axis (s > 0) cross triangle t?
bool crosses(const TriMesh& m, int t, const Eigen::Vector3d& p, int axis) {
  double det;
  Eigen::Vector3d qv;
  if (!on_line(m, t, p, axis, &det, &qv)) return false;
  return (vertex(m, t, 2) - vertex(m, t, 0)).dot(qv) / det > 0;
}

// The cube lattice of cover_object, with per-cube lists of the triangles that can come within a
// cube's sphere and per-line lists of the triangles an axis line passes through: the same answers
// as testing every triangle for every cube, at the cost of the few that matter.
class CubeLattice {
 public:
  CubeLattice(const TriMesh& m, const Eigen::Vector3d& start, double cell, const Eigen::Array3i& n, double radius)
      : m_(m), start_(start), cell_(cell), n_(n), near_(std::size_t(n.prod())) {
    const double scale = std::max({start.cwiseAbs().maxCoeff(), cell * n.maxCoeff(), 1e-3});
    const double reach = radius + 1e-9 * scale;  // only triangles surely beyond reach are left out
    const double touch = 1e-9 * scale;           // a line through a triangle passes through its box
    for (int a = 0; a < 3; ++a) crossing_[a].resize(std::size_t(n.prod() / n[a]));
    for (int t = 0; t < m.triangles.rows(); ++t) {
      Eigen::AlignedBox3d box;
      for (int k = 0; k < 3; ++k) box.extend(vertex(m, t, k));
      const auto lo = first_cube(box.min().array() - reach), hi = last_cube(box.max().array() + reach);
      for (int k = lo.z(); k <= hi.z(); ++k)
        for (int j = lo.y(); j <= hi.y(); ++j)
          for (int i = lo.x(); i <= hi.x(); ++i) near_[index(i, j, k)].push_back(t);
      const auto lo_line = first_cube(box.min().array() - touch), hi_line = last_cube(box.max().array() + touch);
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        for (int y = lo_line[b]; y <= hi_line[b]; ++y)
          for (int z = lo_line[c]; z <= hi_line[c]; ++z) crossing_[a][line(a, y, z)].push_back(t);
      }
    }
  }

  Eigen::Vector3d center(int i, int j, int k) const {
    return start_ + cell_ * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
  }
  const std::vector<int>& near(int i, int j, int k) const { return near_[index(i, j, k)]; }

  // inside_mesh at a cube center: the same three axis rays, tested only against the triangles
  // whose box the ray's line passes through (no other can be crossed).
  bool inside(int i, int j, int k) const {
    const Eigen::Vector3d c = center(i, j, k);
    const int cube[3] = {i, j, k};
    int votes = 0;
    for (int axis = 0; axis < 3; ++axis) {
      int hits = 0;
      for (int t : crossing_[axis][line(axis, cube[(axis + 1) % 3], cube[(axis + 2) % 3])])
        hits += crosses(m_, t, c, axis);
      votes += hits % 2;
    }
    return votes >= 2;
  }

 private:
  // The first and last cube whose center lies at or above `lo` (at or below `hi`), per axis.
  Eigen::Array3i first_cube(const Eigen::Array3d& lo) const {
    Eigen::Array3i out;
    for (int a = 0; a < 3; ++a) out[a] = std::max(0, int(std::ceil((lo[a] - start_[a]) / cell_ - 0.5)));
    return out;
  }
  Eigen::Array3i last_cube(const Eigen::Array3d& hi) const {
    Eigen::Array3i out;
    for (int a = 0; a < 3; ++a) out[a] = std::min(n_[a] - 1, int(std::floor((hi[a] - start_[a]) / cell_ - 0.5)));
    return out;
  }
  // Lines along `axis`, by the cube indices y, z on the next two axes (cyclically).
  std::size_t line(int axis, int y, int z) const {
    return std::size_t(y) + std::size_t(n_[(axis + 1) % 3]) * std::size_t(z);
  }
  std::size_t index(int i, int j, int k) const {
    return std::size_t(i) + std::size_t(n_.x()) * (std::size_t(j) + std::size_t(n_.y()) * k);
  }

  const TriMesh& m_;
  Eigen::Vector3d start_;
  double cell_;
  Eigen::Array3i n_;
  std::vector<std::vector<int>> near_;
  std::array<std::vector<std::vector<int>>, 3> crossing_;  // per axis and line: triangles whose box it passes
};
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
  CubeLattice lattice(m, start, cell, n, radius);
  SphereSet out;
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const Eigen::Vector3d c = lattice.center(i, j, k);
        double d2 = std::numeric_limits<double>::infinity();
        for (int t : lattice.near(i, j, k)) {
          if (d2 <= radius * radius) break;
          d2 = std::min(d2,
                        (formats::closest_point_on_triangle(c, vertex(m, t, 0), vertex(m, t, 1), vertex(m, t, 2)) - c)
                            .squaredNorm());
        }
        // A cube touches the surface when the surface comes within its circumscribed sphere.
        if (d2 <= radius * radius || lattice.inside(i, j, k)) {
          out.centers.push_back(c);
          out.radii.push_back(radius);
        }
      }
  return out;
}

}  // namespace dmgplace::runtime
