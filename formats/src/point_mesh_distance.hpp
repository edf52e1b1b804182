#pragma once
// Distance from points to a triangle mesh, for validating stored surface points (private to
// dmgplace_formats). A uniform grid of triangle boxes keeps the check O(points + triangles): the
// loaders run it on every DMG node, and the formats library must not depend on a BVH library.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/triangle_distance.hpp"

namespace dmgplace::formats::detail {

class SurfaceIndex {
 public:
  // Indices must already be checked; `tol` is the largest query tolerance.
  SurfaceIndex(const TriMesh& m, double tol) : mesh_(m) {
    for (Eigen::Index v = 0; v < m.vertices.rows(); ++v) box_.extend(m.vertices.row(v).transpose());
    // A non-finite extent or tolerance (a caller that did not bound them) finds no point near the
    // surface instead of casting NaN to an index (fuzzing found it); the caller's own checks
    // report the extent.
    if (!std::isfinite(tol) || !box_.min().allFinite() || !box_.max().allFinite() ||
        !std::isfinite(box_.diagonal().norm())) {
      box_ = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
      degenerate_ = true;
      return;
    }
    box_.min().array() -= tol;
    box_.max().array() += tol;
    // About two triangles per cell, at most 64 cells a side.
    const double cells = std::clamp(std::cbrt(double(m.triangles.rows()) / 2), 1.0, 64.0);
    cell_ = std::max(box_.diagonal().maxCoeff() / cells, 1e-12);
    for (int a = 0; a < 3; ++a) dims_[a] = int(std::clamp(std::ceil(box_.diagonal()[a] / cell_), 1.0, 64.0));
    buckets_.resize(std::size_t(dims_[0]) * dims_[1] * dims_[2]);
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
      Eigen::AlignedBox3d tb;
      for (int c = 0; c < 3; ++c) tb.extend(m.vertices.row(m.triangles(t, c)).transpose());
      const auto lo = cell_of(tb.min().array() - tol), hi = cell_of(tb.max().array() + tol);
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int i = lo[0]; i <= hi[0]; ++i) buckets_[index(i, j, k)].push_back(int(t));
    }
  }

  // True when p lies within `tol` (at most the constructor's) of the mesh surface.
  bool near(const Eigen::Vector3d& p, double tol) const {
    if (degenerate_) return false;
    if (!p.allFinite() || box_.exteriorDistance(p) > 0) return false;
    const auto c = cell_of(p.array());
    for (int t : buckets_[index(c[0], c[1], c[2])]) {
      const Eigen::Vector3d a = mesh_.vertices.row(mesh_.triangles(t, 0)).transpose();
      const Eigen::Vector3d b = mesh_.vertices.row(mesh_.triangles(t, 1)).transpose();
      const Eigen::Vector3d d = mesh_.vertices.row(mesh_.triangles(t, 2)).transpose();
      if ((closest_point_on_triangle(p, a, b, d) - p).norm() <= tol) return true;
    }
    return false;
  }

 private:
  std::array<int, 3> cell_of(const Eigen::Array3d& p) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a)
      c[a] = int(
          std::clamp(std::floor((p[a] - box_.min()[a]) / cell_), 0.0, double(dims_[a] - 1)));  // clamp before the cast
    return c;
  }
  std::size_t index(int i, int j, int k) const {
    return std::size_t(i) + std::size_t(dims_[0]) * (j + std::size_t(dims_[1]) * k);
  }

  const TriMesh& mesh_;
  Eigen::AlignedBox3d box_;
  double cell_ = 1;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::vector<int>> buckets_;
  bool degenerate_ = false;
};

}  // namespace dmgplace::formats::detail
