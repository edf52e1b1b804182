#pragma once
// Nearest-node lower bounds of a 1-Lipschitz distance grid: value at the nearest node minus the
// distance to it. One load per query, with values kept as int16 quarter-millimetres rounded down
// (half the memory of floats, so more of it stays in cache), which only lowers the bound.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "dmgplace/runtime/geometry/grid3.hpp"
#include "dmgplace/runtime/system/lanes.hpp"

namespace dmgplace::runtime {

class NodeBoundGrid {
 public:
  // Every `stride`-th node of `g`. Values beyond +-8.19 m are clamped: above only lowers bounds;
  // below keeps them negative, which every caller reads as "not proven free".
  NodeBoundGrid(const Grid3& g, int stride);

  double lower_bound(const Eigen::Vector3d& p) const {
    int c[3];
    const double v = double(values_[node(p, c)]);
    const Eigen::Vector3d at = origin_ + res_ * Eigen::Vector3d(c[0], c[1], c[2]);
    return v * kUnit - (p - at).norm();
  }
  // Start loading p's node: a few queries whose points are known ahead then overlap their misses.
  void prefetch(const Eigen::Vector3d& p) const {
    int c[3];
    __builtin_prefetch(values_.data() + node(p, c));
  }
  double resolution() const { return res_; }
  // lower_bound of N points (structure of arrays x[N], y[N], z[N]) into out[N]; the index and
  // distance arithmetic runs in SIMD lanes (lanes.hpp), the loads are one per point.
  template <int N>
  DMGPLACE_LANES_INLINE void lower_bound_lanes(const double* x, const double* y, const double* z, double* out) const {
    static_assert(N % lanes::W == 0);
    using lanes::D;
    using lanes::I;
    alignas(32) int idx[N];
    alignas(32) double dist[N];
    const D inv = lanes::splat(inv_), res = lanes::splat(res_), half = lanes::splat(0.5);
    for (int h = 0; h < N; h += lanes::W) {
      // Clamped to the grid (a NaN goes to 0: max0 keeps 0 for it), then rounded to the nearest node.
      const D px = lanes::load(x + h), py = lanes::load(y + h), pz = lanes::load(z + h);
      const D ox = lanes::splat(origin_[0]), oy = lanes::splat(origin_[1]), oz = lanes::splat(origin_[2]);
      const D u = lanes::min(lanes::max0((px - ox) * inv), lanes::splat(double(dims_[0] - 1)));
      const D v = lanes::min(lanes::max0((py - oy) * inv), lanes::splat(double(dims_[1] - 1)));
      const D w = lanes::min(lanes::max0((pz - oz) * inv), lanes::splat(double(dims_[2] - 1)));
      const I cx = lanes::to_int(u + half), cy = lanes::to_int(v + half), cz = lanes::to_int(w + half);
      const I index = cx + dims_[0] * (cy + dims_[1] * cz);
      std::memcpy(idx + h, &index, sizeof index);
      const D dx = px - (ox + res * lanes::to_double(cx)), dy = py - (oy + res * lanes::to_double(cy)),
              dz = pz - (oz + res * lanes::to_double(cz));
      lanes::store(dist + h, lanes::sqrt(dx * dx + dy * dy + dz * dz));
    }
    for (int k = 0; k < N; ++k) out[k] = double(values_[std::size_t(idx[k])]) * kUnit - dist[k];
  }

 private:
  // Index of the node nearest p, clamped to the grid; its integer coordinates in c.
  std::size_t node(const Eigen::Vector3d& p, int c[3]) const {
    for (int a = 0; a < 3; ++a) {
      double u = (p[a] - origin_[a]) * inv_;
      u = u > 0 ? u : 0.0;  // also maps NaN to 0
      const double hi = double(dims_[std::size_t(a)] - 1);
      c[a] = int((u < hi ? u : hi) + 0.5);
    }
    return std::size_t(c[0]) + std::size_t(dims_[0]) * (std::size_t(c[1]) + std::size_t(dims_[1]) * std::size_t(c[2]));
  }
  static constexpr double kUnit = 0.00025;  // metres per stored step
  Eigen::Vector3d origin_;
  double res_, inv_;
  std::array<int, 3> dims_;
  std::vector<std::int16_t> values_;
};

}  // namespace dmgplace::runtime
