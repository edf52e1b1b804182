#pragma once
// An OMPL motion validator that checks the same discrete states as OMPL's DiscreteMotionValidator
// (every longest-valid-segment step) but skips those inside intervals the collision checker has
// proved free: a state with clearance c whose bodies move at most v metres per unit of joint
// motion certifies c / v of the segment on both sides of it. States are visited in bisection
// order, so a blocked motion is still found after a few checks. With a checker that proves
// states free in SIMD lanes (ProvenFreeFn): short stretches no certificate reaches (near
// obstacles) are checked 8 states at a time, a state the lane check does not prove taking the single
// check; and a range that lanes reaching half as far as the neighbouring certificate would cover
// is proven by one "span" lane check (each lane proving the states around it), whatever a lane leaves
// going to certified checks.
#include <ompl/base/MotionValidator.h>

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <functional>

namespace dmgplace::runtime {

class CertifiedMotionValidator : public ompl::base::MotionValidator {
 public:
  // q + t * direction is free for |t| <= reach (< 0: q collides); `estimate` (<= reach): how far
  // the same clearances last under the span lane checks' isotropic widening, which decides whether a
  // span lane check is worth trying next to q (directional bounds can make `reach` much longer near a
  // surface the motion slides along, where a lane check would fail).
  struct Certificate {
    double reach, estimate;
  };
  using CertificateFn =
      std::function<Certificate(const Eigen::VectorXd& q, const Eigen::VectorXd& direction, double enough)>;
  // The same with the estimate the reach itself.
  using FreeDistanceFn =
      std::function<double(const Eigen::VectorXd& q, const Eigen::VectorXd& direction, double enough)>;
  static CertificateFn certificate_of(FreeDistanceFn free_distance);
  // Bit k set: every configuration within `reach` (joint-space length, 0: q[k] alone) of q[k]
  // (of `count` <= 8) along +-direction is proven free; unset means undecided.
  using ProvenFreeFn =
      std::function<std::uint32_t(const double* const* q, int count, const Eigen::VectorXd& direction, double reach)>;
  // The callbacks must not check a motion with a CertifiedMotionValidator on their own thread: a
  // motion check keeps its segment, lane check and ranges in per-thread buffers (no allocation per
  // motion). Threads each check their own motions at once.
  CertifiedMotionValidator(const ompl::base::SpaceInformationPtr& si, CertificateFn certificate,
                           ProvenFreeFn proven_free = nullptr);
  CertifiedMotionValidator(const ompl::base::SpaceInformationPtr& si, FreeDistanceFn free_distance,
                           ProvenFreeFn proven_free = nullptr);

  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2) const override;
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2,
                   std::pair<ompl::base::State*, double>& last_valid) const override;
  // checkMotion for a motion whose both ends are known valid (both tree nodes: a shortcut jump,
  // a straight line between two roots): its far end is not checked, so the first certificate
  // lands mid-way, where such a motion is blocked if at all.
  bool checkMotionBetweenValid(const ompl::base::State* s1, const ompl::base::State* s2) const;

 private:
  bool check_motion(const ompl::base::State* s1, const ompl::base::State* s2, bool end_valid) const;
  struct Call;  // one check_motion call (certified_motion_validator.cpp)
  CertificateFn certificate_;
  ProvenFreeFn proven_free_;
  // How often far ends were blocked lately, 1 << 16 meaning always: a running average over about
  // the last 32 motions checked with one. Relaxed: a lost update only shifts which order is tried.
  mutable std::atomic<std::uint32_t> far_blocked_{1u << 15};
  void far_end_was(bool blocked) const;
};

}  // namespace dmgplace::runtime
