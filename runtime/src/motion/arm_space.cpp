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

}  // namespace dmgplace::runtime
