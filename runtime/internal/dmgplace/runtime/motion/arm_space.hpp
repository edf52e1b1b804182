#pragma once
// The joint space of an arm chain as OMPL sees it: bounds from the joint limits, validity from a
// collision checker, and motions checked every `resolution` radians (L2 step, so no joint moves
// more than that between checks).
#include <ompl/base/SpaceInformation.h>

#include <functional>

#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/motion/segment_check.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::runtime {

// < 0: q is invalid; otherwise q is valid and so is q + t * direction for t in [0, result]
// (TwoLayerChecker::free_distance).
using FreeDistanceFn = std::function<double(const Eigen::VectorXd& q, const Eigen::VectorXd& direction, double enough)>;

// With `free_distance`, motions are checked by a CertifiedMotionValidator: the same states at
// `resolution` steps, except those inside an interval the checker proved free.
ompl::base::SpaceInformationPtr make_arm_space(const Kinematics& kin, ValidityFn valid, double resolution,
                                               FreeDistanceFn free_distance = nullptr);
// The space over a two-layer checker: its validity, its certified motions, and its lane proofs
// (short stretches near obstacles state by state, wider ones by span lane checks; AVX2 only).
// `checker` must outlive the space.
ompl::base::SpaceInformationPtr make_arm_space(const Kinematics& kin, const TwoLayerChecker& checker,
                                               double resolution);

}  // namespace dmgplace::runtime
