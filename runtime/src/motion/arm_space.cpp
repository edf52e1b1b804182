#include "dmgplace/runtime/motion/arm_space.hpp"

#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <cmath>

#include "dmgplace/runtime/motion/certified_motion_validator.hpp"

namespace ob = ompl::base;

namespace dmgplace::runtime {

ob::SpaceInformationPtr make_arm_space(const Kinematics& kin, ValidityFn valid, double resolution,
                                       FreeDistanceFn free_distance) {
  const int n = kin.dof();
  auto space = std::make_shared<ob::RealVectorStateSpace>(unsigned(n));
  ob::RealVectorBounds bounds(static_cast<unsigned>(n));
  for (int i = 0; i < n; ++i) {
    bounds.setLow(unsigned(i), kin.lower()[i]);
    bounds.setHigh(unsigned(i), kin.upper()[i]);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker([valid = std::move(valid), n](const ob::State* s) {
    thread_local Eigen::VectorXd q;
    q.resize(n);
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    for (int i = 0; i < n; ++i) q[i] = v->values[i];
    return valid(q);
  });
  si->setStateValidityCheckingResolution(resolution / space->getMaximumExtent());
  if (free_distance) si->setMotionValidator(std::make_shared<CertifiedMotionValidator>(si, std::move(free_distance)));
  si->setup();
  return si;
}

bool path_valid(const std::vector<std::vector<double>>& path, const ValidityFn& valid, double resolution) {
  if (path.empty()) return false;
  Eigen::VectorXd q(Eigen::Index(path[0].size()));
  for (std::size_t i = 0; i < path.size(); ++i) {
    const auto& b = path[i];
    const auto& a = path[i == 0 ? 0 : i - 1];
    // The planners' metric (OMPL's longest valid segment: Euclidean joint-space length), so the
    // states re-checked are the ones a motion validator at this resolution checked.
    double span = 0;
    for (std::size_t k = 0; k < a.size(); ++k) span += (b[k] - a[k]) * (b[k] - a[k]);
    const int steps = std::max(1, int(std::ceil(std::sqrt(span) / resolution)));
    for (int s = 0; s <= steps; ++s) {
      const double t = double(s) / steps;
      for (std::size_t k = 0; k < a.size(); ++k) q[Eigen::Index(k)] = a[k] + t * (b[k] - a[k]);
      if (!valid(q)) return false;
    }
  }
  return true;
}

}  // namespace dmgplace::runtime
