#pragma once
// An OMPL motion validator that checks the same discrete states as OMPL's DiscreteMotionValidator
// (every longest-valid-segment step) but skips those inside intervals the collision checker has
// proved free: a state with clearance c whose bodies move at most v metres per unit of joint
// motion certifies c / v of the segment on both sides of it. States are visited in bisection
// order, so a blocked motion is still found after a few checks. Short stretches no certificate
// reaches (near obstacles) are checked 8 states at a time when the checker can prove states free
// in SIMD lanes (ProvenFreeFn); a state the batch does not prove takes the single check.
#include <ompl/base/MotionValidator.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>

namespace dmgplace::runtime {

class CertifiedMotionValidator : public ompl::base::MotionValidator {
 public:
  using FreeDistanceFn = std::function<double(const Eigen::VectorXd& q, const Eigen::VectorXd& direction, double enough)>;
  // Bit k set: configuration q[k] (of `count` <= 8) is proven free; unset means undecided.
  using ProvenFreeFn = std::function<std::uint32_t(const double* const* q, int count)>;
  CertifiedMotionValidator(const ompl::base::SpaceInformationPtr& si, FreeDistanceFn free_distance,
                           ProvenFreeFn proven_free = nullptr);

  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2) const override;
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2,
                   std::pair<ompl::base::State*, double>& last_valid) const override;

 private:
  FreeDistanceFn free_distance_;
  ProvenFreeFn proven_free_;
};

}  // namespace dmgplace::runtime
