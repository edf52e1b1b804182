#pragma once
// Nearest-node lower bounds of a 1-Lipschitz distance grid: value at the nearest node minus the
// distance to it. One load per query, with values kept as int16 quarter-millimetres rounded down
// (half the memory of floats, so more of it stays in cache), which only lowers the bound.
#include <Eigen/Core>
#include <array>
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
