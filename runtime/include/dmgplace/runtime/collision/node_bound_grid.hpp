#pragma once
// Nearest-node lower bounds of a 1-Lipschitz distance grid: value at the nearest node minus the
// distance to it. One load per query, with values kept as int16 quarter-millimetres rounded down
// (half the memory of floats, so more of it stays in cache), which only lowers the bound.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dmgplace/runtime/geometry/grid3.hpp"

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
  // lower_bound of 8 points (structure of arrays x[8], y[8], z[8]) into out[8]; the index and
  // distance arithmetic runs in SIMD lanes, the loads are one per point.
  template <int N>
  inline __attribute__((always_inline)) void lower_bound_lanes(const double* x, const double* y, const double* z, double* out) const {
    alignas(64) int idx[N];
    alignas(64) double dx[N], dy[N], dz[N];
    const double hx = double(dims_[0] - 1), hy = double(dims_[1] - 1), hz = double(dims_[2] - 1);
    for (int k = 0; k < N; ++k) {
      double u = (x[k] - origin_[0]) * inv_, v = (y[k] - origin_[1]) * inv_, w = (z[k] - origin_[2]) * inv_;
      u = u > 0 ? (u < hx ? u : hx) : 0.0;
      v = v > 0 ? (v < hy ? v : hy) : 0.0;
      w = w > 0 ? (w < hz ? w : hz) : 0.0;
      const int cx = int(u + 0.5), cy = int(v + 0.5), cz = int(w + 0.5);
      idx[k] = cx + dims_[0] * (cy + dims_[1] * cz);
      dx[k] = x[k] - (origin_[0] + res_ * cx);
      dy[k] = y[k] - (origin_[1] + res_ * cy);
      dz[k] = z[k] - (origin_[2] + res_ * cz);
    }
    for (int k = 0; k < N; ++k) out[k] = double(values_[std::size_t(idx[k])]) * kUnit - std::sqrt(dx[k] * dx[k] + dy[k] * dy[k] + dz[k] * dz[k]);
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
