#include "dmgplace/tools/robot/sphere_cover.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/winding_number.hpp"
#include "dmgplace/tools/geometry/tessellate.hpp"

namespace dmgplace::tools {
namespace {

void sample_surface(const TriMesh& m, double spacing, std::vector<Eigen::Vector3d>& out) {
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = m.vertices.row(m.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = m.vertices.row(m.triangles(t, 2)).transpose();
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, int(std::ceil(longest / spacing)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) out.push_back(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
  }
}

constexpr double kMaxSamples = 2e7;  // 480 MB of points

// Counts the samples before making them: a link a kilometre long at 5 mm spacing would need
// ~10^15 points (the bake ran out of memory at 45 MB/s instead of saying so).
void check_sample_budget(const std::vector<TriMesh>& meshes, double spacing) {
  double total = 0;
  for (const auto& m : meshes) {
    Eigen::AlignedBox3d box;
    for (Eigen::Index i = 0; i < m.vertices.rows(); ++i) box.extend(m.vertices.row(i).transpose());
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
      const Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)).transpose();
      const Eigen::Vector3d b = m.vertices.row(m.triangles(t, 1)).transpose();
      const Eigen::Vector3d c = m.vertices.row(m.triangles(t, 2)).transpose();
      const double n = std::ceil(std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()}) / spacing) + 1;
      total += n * (n + 1) / 2;
    }
    if (!box.isEmpty()) total += (box.sizes() / (2 * spacing)).array().ceil().prod();
  }
  if (!(total <= kMaxSamples))
    throw Error("sphere cover", "",
                "the link's geometry needs about " + std::to_string(total) + " samples at a spacing of " +
                    std::to_string(spacing) + " m, more than " + std::to_string(kMaxSamples) +
                    " (is the geometry in millimetres? else raise --sphere-spacing)");
}

}  // namespace

std::vector<Eigen::Vector3d> sample_solid(const std::vector<Shape>& shapes, double spacing) {
  if (!(spacing > 0)) throw Error("sphere cover", "", "sample spacing must be positive");
  std::vector<TriMesh> meshes;
  for (const auto& s : shapes) meshes.push_back(tessellate(s, 24));
  check_sample_budget(meshes, spacing);
  std::vector<Eigen::Vector3d> pts;
  for (const auto& m : meshes) {
    sample_surface(m, spacing, pts);
    Eigen::AlignedBox3d box;
    for (Eigen::Index i = 0; i < m.vertices.rows(); ++i) box.extend(m.vertices.row(i).transpose());
    // Interior on a coarser grid (every 2 spacings): interior points only matter for the volume.
    const double step = 2 * spacing;
    for (double x = box.min().x() + step / 2; x < box.max().x(); x += step)
      for (double y = box.min().y() + step / 2; y < box.max().y(); y += step)
        for (double z = box.min().z() + step / 2; z < box.max().z(); z += step) {
          Eigen::Vector3d p(x, y, z);
          if (winding_number(m, p) > 0.5) pts.push_back(p);
        }
  }
  return pts;
}

std::vector<Sphere> cover_with_spheres(const std::vector<Shape>& shapes, const SphereCoverOptions& opt) {
  std::vector<Eigen::Vector3d> pts = sample_solid(shapes, opt.sample_spacing);
  if (pts.empty()) return {};
  // Recursive bisection of the cluster that over-approximates most, until every sphere is tight.
  // Tightness: radius minus half the median bounding-box extent (a slice of a cylinder of radius r
  // has excess sqrt(r^2 + t^2/4) - r, which shrinks as slices thin). Deterministic.
  struct Cluster {
    std::vector<int> idx;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radius = 0, excess = 0;
    Eigen::AlignedBox3d box;
  };
  auto farthest = [&](const std::vector<int>& idx, const Eigen::Vector3d& c, int& at) {
    double r2 = -1;
    for (int i : idx)
      if (const double d = (pts[std::size_t(i)] - c).squaredNorm(); d > r2) r2 = d, at = i;
    return std::sqrt(r2);
  };
  auto make = [&](std::vector<int> idx) {
    Eigen::AlignedBox3d box;
    for (int i : idx) box.extend(pts[std::size_t(i)]);
    Cluster c{std::move(idx), box.center(), 0, 0, box};
    int far = 0;
    c.radius = farthest(c.idx, c.center, far);
    Eigen::Vector3d e = box.sizes();
    std::sort(e.data(), e.data() + 3);
    c.excess = c.radius > opt.max_radius ? c.radius : c.radius - 0.5 * e[1];
    return c;
  };
  // The cluster's sphere shrunk toward its smallest enclosing ball: Badoiu-Clarkson steps (the
  // center moves 1/(i+2) of the way to the farthest point), the best center seen kept. The radius
  // is always the exact farthest distance from the kept center, so the sphere still covers.
  auto shrink = [&](Cluster& c) {
    Eigen::Vector3d at = c.center;
    int far = 0;
    farthest(c.idx, at, far);
    for (int i = 0; i < 64; ++i) {
      at += (pts[std::size_t(far)] - at) / double(i + 2);
      if (const double r = farthest(c.idx, at, far); r < c.radius) c.radius = r, c.center = at;
    }
  };
  // Of the three axes, the cut at the box's middle whose two spheres hold the least volume.
  auto split = [&](const Cluster& c, Cluster& lo_out, Cluster& hi_out) {
    bool found = false;
    double best = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double mid = c.box.center()[axis];
      std::vector<int> lo, hi;
      for (int i : c.idx) (pts[std::size_t(i)][axis] < mid ? lo : hi).push_back(i);
      if (!lo.empty() && !hi.empty()) {
        Cluster a = make(std::move(lo)), b = make(std::move(hi));
        const double v = std::pow(a.radius, 3) + std::pow(b.radius, 3);
        if (!found || v < best) found = true, best = v, lo_out = std::move(a), hi_out = std::move(b);
      }
    }
    return found;
  };
  std::vector<int> all(pts.size());
  std::iota(all.begin(), all.end(), 0);
  std::vector<Cluster> clusters{make(all)};
  while (int(clusters.size()) < opt.max_spheres) {
    auto worst = std::max_element(clusters.begin(), clusters.end(),
                                  [](const Cluster& a, const Cluster& b) { return a.excess < b.excess; });
    if (worst->excess <= opt.max_excess || worst->idx.size() < 2) break;
    Cluster lo, hi;
    if (!split(*worst, lo, hi)) break;
    *worst = std::move(lo);
    clusters.push_back(std::move(hi));
  }
  std::vector<Sphere> out;
  // Inflate by the sample spacing: any geometry point is within one spacing of a sample.
  for (auto& c : clusters) {
    shrink(c);
    out.push_back({c.center, c.radius + opt.sample_spacing});
  }
  return out;
}

}  // namespace dmgplace::tools
