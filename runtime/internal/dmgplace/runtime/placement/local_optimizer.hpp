#pragma once
// OPTIMIZELOCALLY: from a reached placement, slide and turn the object on its support along the
// objective's gradient, moving the arm by damped-least-squares steps (the Jacobian's
// pseudo-inverse) toward each displaced pose. A step is kept only when the object stays stable at
// the same height, the objective improves and the joint-space segment is collision-free at the
// checking resolution; otherwise the step is halved, down to a minimum.
#include <random>

#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/motion/segment_check.hpp"
#include "dmgplace/runtime/types.hpp"
#include "dmgplace/runtime/placement/objective.hpp"
#include "dmgplace/runtime/placement/search_space.hpp"
#include "dmgplace/runtime/robot/ik.hpp"

namespace dmgplace::runtime {

struct LocalOptimum {
  JointPath steps;                       // configurations after the start, each reached by a valid segment
  std::vector<Eigen::Isometry3d> poses;  // resting pose after each step
  std::vector<double> values;            // objective after each step (increasing)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // resting pose reached (the last step's)
  double objective = 0;
  double start_objective = 0;  // at the start pose
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

}  // namespace dmgplace::runtime
