#include "dmgplace/runtime/motion/arm_space.hpp"

#include <ompl/base/spaces/RealVectorStateProjections.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <cmath>

#include "dmgplace/runtime/motion/certified_motion_validator.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace ob = ompl::base;

namespace dmgplace::runtime {

namespace {
// The joint space with a cheap default projection: the first two joints, as MoveIt configures
// arms (the shoulder moves the arm most). OMPL's default for more than two dimensions draws a
// random matrix, orthonormalises it and samples states to size its cells, most of the cost of
// setting the space up, which every query pays. Planners that
// use projections (KPIECE, SBL, ...) get one; ours ignore it.
class ArmStateSpace : public ob::RealVectorStateSpace {
 public:
  using ob::RealVectorStateSpace::RealVectorStateSpace;
  void registerProjections() override {
    std::vector<unsigned> keep{0};
    if (getDimension() > 1) keep.push_back(1);
    registerDefaultProjection(std::make_shared<ob::RealVectorOrthogonalProjectionEvaluator>(this, keep));
  }
};

ob::SpaceInformationPtr make_space(const Kinematics& kin, ValidityFn valid, double resolution,
                                   CertifiedMotionValidator::CertificateFn certificate,
                                   CertifiedMotionValidator::ProvenFreeFn proven_free) {
  const int n = kin.dof();
  auto space = std::make_shared<ArmStateSpace>(unsigned(n));
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
  if (certificate)
    si->setMotionValidator(
        std::make_shared<CertifiedMotionValidator>(si, std::move(certificate), std::move(proven_free)));
  si->setup();
  return si;
}
}  // namespace

ob::SpaceInformationPtr make_arm_space(const Kinematics& kin, ValidityFn valid, double resolution,
                                       FreeDistanceFn free_distance) {
  return make_space(kin, std::move(valid), resolution,
                    CertifiedMotionValidator::certificate_of(std::move(free_distance)), nullptr);
}

ob::SpaceInformationPtr make_arm_space(const Kinematics& kin, const TwoLayerChecker& checker, double resolution) {
  // Lane proofs pay only with AVX2: on the portable path the planners are slower with them
  // (docs/motion.md, "Lane checks: 8 configurations per call").
  CertifiedMotionValidator::ProvenFreeFn proven_free;
  if (simd_path() == SimdPath::Avx2)
    proven_free = [&checker](const double* const* q, int count, const Eigen::VectorXd& direction, double reach) {
      return checker.proven_free_along(q, count, direction, reach);
    };
  return make_space(
      kin, [&checker](const Eigen::VectorXd& q) { return checker.is_free(q); }, resolution,
      [&checker](const Eigen::VectorXd& q, const Eigen::VectorXd& dir, double enough) {
        CertifiedMotionValidator::Certificate c{};
        c.reach = checker.free_distance(q, dir, enough, &c.estimate);
        return c;
      },
      std::move(proven_free));
}

}  // namespace dmgplace::runtime
