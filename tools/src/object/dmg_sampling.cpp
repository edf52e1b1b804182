// Surface sampling, crease regions and the sample hash grid for the DMG builder.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <unordered_map>

#include "dmg_internal.hpp"

namespace dmgplace::tools::detail {

SurfaceSamples sample_surface(const TriMesh& mesh, double spacing) {
  SurfaceSamples s;
  s.spacing = spacing;
  std::mt19937_64 rng(20180901);  // fixed: the same mesh always gives the same DMG
  std::uniform_real_distribution<double> u(0, 1);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() == 0) continue;
    // Expected count area / spacing^2, rounded at random so small triangles are still covered on average.
    const double expected = 0.5 * n.norm() / (spacing * spacing);
    const int count = int(expected) + (u(rng) < expected - std::floor(expected) ? 1 : 0);
    for (int i = 0; i < count; ++i) {
      double x = u(rng), y = u(rng);
      if (x + y > 1) x = 1 - x, y = 1 - y;
      s.position.push_back(a + x * (b - a) + y * (c - a));
      s.normal.push_back(n.normalized());
      s.triangle.push_back(int(t));
    }
  }
  return s;
}

std::vector<int> crease_regions(const TriMesh& mesh, double crease_angle) {
  const Eigen::Index nt = mesh.triangles.rows();
  std::vector<Eigen::Vector3d> normal(nt);
  for (Eigen::Index t = 0; t < nt; ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose();
    normal[t] = (mesh.vertices.row(mesh.triangles(t, 1)).transpose() - a)
                    .cross(mesh.vertices.row(mesh.triangles(t, 2)).transpose() - a)
                    .normalized();
  }
  std::vector<int> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::unordered_map<std::uint64_t, int> edge_owner;  // undirected edge -> first triangle
  const double cos_crease = std::cos(crease_angle);
  for (Eigen::Index t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t i = std::uint32_t(mesh.triangles(t, k)), j = std::uint32_t(mesh.triangles(t, (k + 1) % 3));
      const std::uint64_t key = std::min(i, j) << 32 | std::max(i, j);
      auto [it, fresh] = edge_owner.emplace(key, int(t));
      if (!fresh && normal[it->second].dot(normal[t]) >= cos_crease) parent[find(int(t))] = find(it->second);
    }
  std::vector<int> region(nt);
  for (Eigen::Index t = 0; t < nt; ++t) region[t] = find(int(t));
  return region;
}

SampleGrid::SampleGrid(const std::vector<Eigen::Vector3d>& points, double cell) : points_(points), cell_(cell) {
  std::size_t buckets = 64;
  while (buckets < 2 * points.size()) buckets *= 2;
  start_.assign(buckets + 1, 0);
  std::vector<long> h(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) ++start_[(h[i] = hash(key(points[i]))) + 1];
  std::partial_sum(start_.begin(), start_.end(), start_.begin());
  order_.resize(points.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i) order_[fill[h[i]]++] = int(i);
}

std::array<long, 3> SampleGrid::key(const Eigen::Vector3d& p) const {
  return {long(std::floor(p.x() / cell_)), long(std::floor(p.y() / cell_)), long(std::floor(p.z() / cell_))};
}

long SampleGrid::hash(const std::array<long, 3>& k) const {
  const std::uint64_t h =
      std::uint64_t(k[0]) * 73856093ull ^ std::uint64_t(k[1]) * 19349663ull ^ std::uint64_t(k[2]) * 83492791ull;
  return long(h & (start_.size() - 2));  // bucket count is a power of two
}

int SampleGrid::nearest(const Eigen::Vector3d& p, double max_radius) const {
  int best = -1;
  double best_d = max_radius * max_radius;
  // Rings of cells until the radius is covered.
  const long rings = long(std::ceil(max_radius / cell_));
  const auto k = key(p);
  for (long dx = -rings; dx <= rings; ++dx)
    for (long dy = -rings; dy <= rings; ++dy)
      for (long dz = -rings; dz <= rings; ++dz) {
        const long h = hash({k[0] + dx, k[1] + dy, k[2] + dz});
        for (int i = start_[h]; i < start_[h + 1]; ++i) {
          const double d = (points_[order_[i]] - p).squaredNorm();
          if (d <= best_d) best_d = d, best = order_[i];
        }
      }
  return best;
}

}  // namespace dmgplace::tools::detail
