#pragma once
// The largest signed distance of any of a set of points above a plane, asked for many planes:
// a tree of boxes over the points skips every box that lies below `threshold` of the plane, so a
// convex hull's check of all mesh vertices against each of its faces reads the few near it.
#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <numeric>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::formats::detail {

class PointsAbovePlane {
 public:
  explicit PointsAbovePlane(const RowMatrixX3d& points) : points_(points), order_(std::size_t(points.rows())) {
    std::iota(order_.begin(), order_.end(), 0);
    if (!order_.empty()) build(0, order_.size());
  }

  // Whether some point p has (p - a).u > threshold, u a unit normal: each point tested exactly
  // as a scan of all of them would, and boxes skipped only where they are clearly below (by half
  // the threshold, far beyond the rounding of a box's bound).
  bool any_above(const Eigen::Vector3d& a, const Eigen::Vector3d& u, double threshold) const {
    if (nodes_.empty()) return false;
    const Eigen::Vector3d abs_u = u.cwiseAbs();
    std::vector<int> stack{0};
    while (!stack.empty()) {
      const Node& n = nodes_[std::size_t(stack.back())];
      stack.pop_back();
      if ((n.center - a).dot(u) + n.half.dot(abs_u) <= 0.5 * threshold) continue;
      if (n.left < 0) {
        for (std::size_t k = n.begin; k < n.end; ++k)
          if ((points_.row(order_[k]).transpose() - a).dot(u) > threshold) return true;
        continue;
      }
      stack.push_back(n.left);
      stack.push_back(n.right);
    }
    return false;
  }

 private:
  struct Node {
    Eigen::Vector3d center, half;
    std::size_t begin, end;
    int left = -1, right = -1;  // -1: a leaf
  };
  static constexpr std::size_t kLeaf = 8;

  int build(std::size_t begin, std::size_t end) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t k = begin; k < end; ++k) {
      lo = lo.cwiseMin(points_.row(order_[k]).transpose());
      hi = hi.cwiseMax(points_.row(order_[k]).transpose());
    }
    const int at = int(nodes_.size());
    nodes_.push_back({(lo + hi) / 2, (hi - lo) / 2, begin, end});
    if (end - begin <= kLeaf) return at;
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    const std::size_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + long(begin), order_.begin() + long(mid), order_.begin() + long(end),
                     [&](Eigen::Index x, Eigen::Index y) { return points_(x, axis) < points_(y, axis); });
    const int left = build(begin, mid), right = build(mid, end);
    nodes_[std::size_t(at)].left = left;
    nodes_[std::size_t(at)].right = right;
    return at;
  }

  const RowMatrixX3d& points_;
  std::vector<Eigen::Index> order_;
  std::vector<Node> nodes_;
};

}  // namespace dmgplace::formats::detail
