#include "dmgplace/runtime/motion/arm_space.hpp"

#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <cmath>

#include "dmgplace/runtime/motion/certified_motion_validator.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace ob = ompl::base;

namespace dmgplace::runtime {

namespace {
ob::SpaceInformationPtr make_space(const Kinematics& kin, ValidityFn valid, double resolution, FreeDistanceFn free_distance,
                                   CertifiedMotionValidator::ProvenFreeFn proven_free) {
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
  if (free_distance)
    si->setMotionValidator(std::make_shared<CertifiedMotionValidator>(si, std::move(free_distance), std::move(proven_free)));
  si->setup();
  return si;
}
}  // namespace

ob::SpaceInformationPtr make_arm_space(const Kinematics& kin, ValidityFn valid, double resolution,
                                       FreeDistanceFn free_distance) {
  return make_space(kin, std::move(valid), resolution, std::move(free_distance), nullptr);
}

ob::SpaceInformationPtr make_arm_space(const Kinematics& kin, const TwoLayerChecker& checker, double resolution) {
  // Batch proofs pay only with AVX2: on the portable path 8 lanes cost more than 8 plain checks
  // (docs/motion.md, "Batch checks").
  CertifiedMotionValidator::ProvenFreeFn batch;
  if (simd_path() == SimdPath::Avx2) batch = [&checker](const double* const* q, int count) { return checker.proven_free(q, count); };
  return make_space(
      kin, [&checker](const Eigen::VectorXd& q) { return checker.is_free(q); }, resolution,
      [&checker](const Eigen::VectorXd& q, const Eigen::VectorXd& dir, double enough) { return checker.free_distance(q, dir, enough); },
      std::move(batch));
}

}  // namespace dmgplace::runtime
