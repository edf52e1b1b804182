#include "dmgplace/runtime/motion/certified_motion_validator.hpp"

#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <cmath>

namespace ob = ompl::base;

namespace dmgplace::runtime {
namespace {
Eigen::VectorXd to_eigen(const ob::State* s, unsigned n) {
  const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
  return Eigen::Map<const Eigen::VectorXd>(v->values, n);
}
}  // namespace

CertifiedMotionValidator::CertifiedMotionValidator(const ob::SpaceInformationPtr& si, FreeDistanceFn free_distance)
    : ob::MotionValidator(si), free_distance_(std::move(free_distance)) {}

bool CertifiedMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2) const {
  const unsigned n = si_->getStateDimension();
  const Eigen::VectorXd a = to_eigen(s1, n), b = to_eigen(s2, n);
  const double length = (b - a).norm();
  const int steps = std::max(1, int(std::ceil(length / si_->getStateSpace()->getLongestValidSegmentLength())));
  const Eigen::VectorXd dir = length > 0 ? Eigen::VectorXd((b - a) / length) : Eigen::VectorXd::Zero(n);
  const double h = length / steps;
  // A certificate is symmetric (speeds bound |direction|): state i proves states i-k .. i+k.
  auto check = [&](int i, int& k) {
    const double fd = free_distance_(a + (i * h) * dir, dir);
    if (fd < 0) return false;
    k = h > 0 ? int(std::min(fd / h, double(steps))) : steps;
    return true;
  };
  int k = 0;
  if (!check(steps, k)) {  // the far end first: a bad goal is found at once
    ++invalid_;
    return false;
  }
  // Unchecked index ranges [lo, hi] (state 0 is valid by contract), bisected breadth first as
  // OMPL's discrete validator does, minus what each checked state certifies around itself.
  thread_local std::vector<std::pair<int, int>> queue;
  queue.assign(1, {1, steps - 1 - k});
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto [lo, hi] = queue[head];
    if (lo > hi) continue;
    const int mid = (lo + hi) / 2;
    if (!check(mid, k)) {
      ++invalid_;
      return false;
    }
    queue.emplace_back(lo, mid - k - 1);
    queue.emplace_back(mid + k + 1, hi);
  }
  ++valid_;
  return true;
}

bool CertifiedMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2,
                                           std::pair<ob::State*, double>& last_valid) const {
  // Sequential from s1 so the last valid state is known; certified stretches are skipped too.
  const unsigned n = si_->getStateDimension();
  const Eigen::VectorXd a = to_eigen(s1, n), b = to_eigen(s2, n);
  const double length = (b - a).norm();
  const int steps = std::max(1, int(std::ceil(length / si_->getStateSpace()->getLongestValidSegmentLength())));
  const Eigen::VectorXd dir = length > 0 ? Eigen::VectorXd((b - a) / length) : Eigen::VectorXd::Zero(n);
  const double h = length / steps;
  double covered = 0;
  for (int i = 1; i <= steps; ++i) {
    const double t = i * h;
    if (t <= covered && i < steps) continue;
    const double ahead = free_distance_(a + t * dir, dir);
    if (ahead < 0) {
      last_valid.second = double(i - 1) / steps;
      if (last_valid.first) si_->getStateSpace()->interpolate(s1, s2, last_valid.second, last_valid.first);
      ++invalid_;
      return false;
    }
    covered = t + ahead;
  }
  ++valid_;
  return true;
}

}  // namespace dmgplace::runtime
