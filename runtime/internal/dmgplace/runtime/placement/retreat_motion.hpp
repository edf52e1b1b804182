#pragma once
// The retreat after release, as a motion (beyond the paper, which leaves retreat to future work):
// once the open hand has withdrawn clear of the placed object (retreat.hpp), an arm motion from
// there to a safe configuration (q0, or the query's retreat_configuration), with the placed
// object an obstacle like the scene. Bidirectional RRT-Connect over a validity test that settles
// most states with the empty-handed two-layer checker and the robot's sphere cover against the
// object's bounding ball, and asks the exact checker (object included, nothing may touch it)
// only where a sphere reaches that ball.
#include <Eigen/Geometry>
#include <vector>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/motion/free_motion.hpp"
#include "dmgplace/runtime/types.hpp"

namespace dmgplace::runtime {

struct RetreatScene {
  const Kinematics* kin = nullptr;
  const TwoLayerChecker* arm = nullptr;                       // empty-handed, fingers open, against the scene
  const ExactChecker* placed = nullptr;                       // the same robot with the object as an obstacle
  const std::vector<formats::LinkSphere>* spheres = nullptr;  // their union covers every link
  Eigen::Vector3d object_center = Eigen::Vector3d::Zero();    // the placed object's bounding ball (world)
  double object_radius = 0;
};

using RetreatBudget = MotionBudget;

// Whether q is free of the scene and of the placed object.
bool retreat_state_free(const RetreatScene& scene, const Eigen::VectorXd& q);

// The approach retraced: from `from` straight to the latest waypoint of `approach` (q0 ... the
// placement) from which the approach back to its start is free, then back along it. The arm came
// in that way holding the object, so with the hand open and the object left behind it is most
// often free, and costs segment checks instead of a search. Empty when no such path is free.
JointPath retrace_approach(const RetreatScene& scene, const Eigen::VectorXd& from, const JointPath& approach,
                           double resolution);

// A path from `from` to `to` (both ends included, every segment free at budget.resolution), or
// empty when none was found within the budget (or an end is not free). `tree`: as for
// plan_free_motion, the start tree of earlier retreats from `from`.
JointPath plan_retreat_motion(const RetreatScene& scene, const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                              const RetreatBudget& budget, MotionTree* tree = nullptr);

}  // namespace dmgplace::runtime
