#include "dmgplace/runtime/motion/segment_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dmgplace::runtime {

int segment_steps(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution) {
  const double steps = std::ceil((b - a).norm() / resolution);
  // NaN or a huge span: one step, so the caller's validity check sees the (invalid) end state.
  if (!(steps >= 1)) return 1;
  return int(std::min(steps, double(std::numeric_limits<int>::max() / 2)));
}

bool segment_valid(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution, const ValidityFn& valid) {
  const int steps = segment_steps(a, b, resolution);
  for (int i = 1; i <= steps; ++i)
    if (!valid(i == steps ? b : Eigen::VectorXd(a + (b - a) * (double(i) / steps)))) return false;
  return true;
}

bool path_valid(const std::vector<std::vector<double>>& path, const ValidityFn& valid, double resolution) {
  if (path.empty()) return false;
  auto at = [&](std::size_t i) {
    return Eigen::Map<const Eigen::VectorXd>(path[i].data(), Eigen::Index(path[i].size()));
  };
  Eigen::VectorXd prev = at(0);
  if (!valid(prev)) return false;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::VectorXd next = at(i);
    if (next.size() != prev.size() || !segment_valid(prev, next, resolution, valid)) return false;
    prev = next;
  }
  return true;
}

}  // namespace dmgplace::runtime
