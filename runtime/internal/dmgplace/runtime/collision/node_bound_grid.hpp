#pragma once
// Nearest-node lower bounds of a 1-Lipschitz distance grid: value at the nearest node minus the
// distance to it. One load per query, with values kept as int16 quarter-millimetres rounded down
// (half the memory of floats, so more of it stays in cache), which only lowers the bound.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
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
  // Bounds from the corners of p's cell (p clamped into the grid): for each corner, its stored
  // value (rounded down, or back up) and its distance to p. The corner away from the nearest
  // obstacle gives nearly the value at p from below, the corner towards it from above, where
  // the nearest node alone loses up to its distance to p: eight loads instead of one.
  double cell_lower_bound(const Eigen::Vector3d& p) const {
    double best = -std::numeric_limits<double>::infinity();
    corners(p, [&](double v, double d) { best = std::max(best, v * kUnit - d); });
    return best;
  }
  // An upper bound (valid below the band, where values are not clamped): below a ball's radius,
  // an obstacle reaches into the ball around p.
  double upper_bound(const Eigen::Vector3d& p) const {
    double best = std::numeric_limits<double>::infinity();
    corners(p, [&](double v, double d) { best = std::min(best, (v + kRoundedDown) * kUnit + d); });
    return best + kValueError;
  }
  // Start loading p's node: a few queries whose points are known ahead then overlap their misses.
  void prefetch(const Eigen::Vector3d& p) const {
    int c[3];
    __builtin_prefetch(values_.data() + node(p, c));
  }
  double resolution() const { return res_; }
  // lower_bound of lanes::WF points (structure of arrays) into out, in floats: the index and
  // distance arithmetic in SIMD lanes (lanes.hpp), the loads one per point. Any node gives a valid
  // bound, so the rounded index arithmetic is harmless; the rounded distance to the node and value
  // are the caller's margin to cover (SphereFieldChecker::lane_margin).
  DMGPLACE_LANES_INLINE void lower_bound_lanes(const float* x, const float* y, const float* z, float* out) const {
    using lanes::F;
    using lanes::MF;
    using lanes::splatf;
    const F inv = splatf(float(inv_)), res = splatf(float(res_)), half = splatf(0.5f);
    const F ox = splatf(float(origin_[0])), oy = splatf(float(origin_[1])), oz = splatf(float(origin_[2]));
    const F px = lanes::load(x), py = lanes::load(y), pz = lanes::load(z);
    const F u = lanes::min(lanes::max0((px - ox) * inv), splatf(float(dims_[0] - 1)));
    const F v = lanes::min(lanes::max0((py - oy) * inv), splatf(float(dims_[1] - 1)));
    const F w = lanes::min(lanes::max0((pz - oz) * inv), splatf(float(dims_[2] - 1)));
    const MF cx = __builtin_convertvector(u + half, MF), cy = __builtin_convertvector(v + half, MF),
             cz = __builtin_convertvector(w + half, MF);
    const MF index = cx + dims_[0] * (cy + dims_[1] * cz);
    const F dx = px - (ox + res * __builtin_convertvector(cx, F)),
            dy = py - (oy + res * __builtin_convertvector(cy, F)),
            dz = pz - (oz + res * __builtin_convertvector(cz, F));
    alignas(32) int idx[lanes::WF];
    alignas(32) float dist[lanes::WF];
    std::memcpy(idx, &index, sizeof index);
    lanes::store(dist, lanes::sqrt(dx * dx + dy * dy + dz * dz));
    for (int k = 0; k < lanes::WF; ++k) out[k] = float(values_[std::size_t(idx[k])]) * float(kUnit) - dist[k];
  }

 private:
  // f(stored value, distance to p) for each corner of p's cell.
  template <class F>
  void corners(const Eigen::Vector3d& p, F&& f) const {
    int c[3], n[3];
    for (int a = 0; a < 3; ++a) {
      n[a] = dims_[std::size_t(a)] > 1 ? 2 : 1;
      const double last = double(dims_[std::size_t(a)] - n[a]);  // the last cell's first corner
      double u = (p[a] - origin_[a]) * inv_;
      u = u > 0 ? u : 0.0;  // also maps NaN to 0
      c[a] = int(u < last ? u : last);
    }
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const std::size_t at =
              std::size_t(c[0] + i) +
              std::size_t(dims_[0]) * (std::size_t(c[1] + j) + std::size_t(dims_[1]) * std::size_t(c[2] + k));
          f(double(values_[at]), (p - (origin_ + res_ * Eigen::Vector3d(c[0] + i, c[1] + j, c[2] + k))).norm());
        }
  }
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
  static constexpr double kUnit = 0.00025;     // metres per stored step
  static constexpr double kRoundedDown = 2;    // steps a stored value may lie below the grid's (see the constructor)
  static constexpr double kValueError = 1e-6;  // the grid's float values against the distances they store
  Eigen::Vector3d origin_;
  double res_, inv_;
  std::array<int, 3> dims_;
  std::vector<std::int16_t> values_;
};

}  // namespace dmgplace::runtime
