#pragma once
// OPTIMIZELOCALLY: from a reached placement, slide and turn the object on its support along the
// objective's gradient, moving the arm by damped-least-squares steps (the Jacobian's
// pseudo-inverse) toward each displaced pose. A step is kept only when the object stays stable at
// the same height, the objective improves and the joint-space segment is collision-free at the
// checking resolution; otherwise the step is halved, down to a minimum.
#include <random>

#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/types.hpp"
#include "dmgplace/runtime/placement/objective.hpp"
#include "dmgplace/runtime/placement/search_space.hpp"
#include "dmgplace/runtime/robot/ik.hpp"

namespace dmgplace::runtime {

struct LocalOptimum {
  JointPath steps;  // configurations after the start, each reached by a valid segment
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // resting pose reached
  double objective = 0;
  int iterations = 0;
};

struct LocalProblem {
  const Kinematics* kin = nullptr;
  const SearchSpace* space = nullptr;
  const Objective* objective = nullptr;
  const TwoLayerChecker* checker = nullptr;  // the grasp's collision space
  Eigen::Isometry3d tcp_in_object = Eigen::Isometry3d::Identity();
  int face = -1, region = -1;
  double lift = 0;
};

LocalOptimum optimize_locally(const LocalProblem& p, const Eigen::VectorXd& q_start, const Eigen::Isometry3d& resting,
                              const PlacementOptions& o);

// Joint-space segment valid at `resolution` (max joint step, rad) under `valid`.
bool segment_valid(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution,
                   const std::function<bool(const Eigen::VectorXd&)>& valid);

}  // namespace dmgplace::runtime
