#pragma once
// An OMPL motion validator that checks the same discrete states as OMPL's DiscreteMotionValidator
// (every longest-valid-segment step) but skips those inside intervals the collision checker has
// proved free: a state with clearance c whose bodies move at most v metres per unit of joint
// motion certifies c / v of the segment on both sides of it. States are visited in bisection
// order, so a blocked motion is still found after a few checks.
#include <ompl/base/MotionValidator.h>

#include <Eigen/Core>
#include <functional>

namespace dmgplace::runtime {

class CertifiedMotionValidator : public ompl::base::MotionValidator {
 public:
  using FreeDistanceFn = std::function<double(const Eigen::VectorXd& q, const Eigen::VectorXd& direction, double enough)>;
  CertifiedMotionValidator(const ompl::base::SpaceInformationPtr& si, FreeDistanceFn free_distance);

  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2) const override;
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2,
                   std::pair<ompl::base::State*, double>& last_valid) const override;

 private:
  FreeDistanceFn free_distance_;
};

}  // namespace dmgplace::runtime
