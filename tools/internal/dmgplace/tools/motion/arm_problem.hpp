#pragma once
// One arm motion-planning problem made ready to solve: robot artifact, scene, start and goal, a
// workspace distance field for the fast collision layer, and the exact checker.
#include <filesystem>
#include <memory>
#include <optional>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"

namespace dmgplace::tools {

struct ArmProblemOptions {
  double sdf_resolution = 0.02;  // metres
  double sdf_band = 0.25;        // metres
  double reach = 1.2;            // half-width of the workspace grid around the arm base
  bool exact_primitives = true;  // the fast layer also uses the scene's exact primitives (when all are)
};

struct ArmProblem {
  formats::RobotArtifact robot;
  Scene scene;
  std::unique_ptr<runtime::Kinematics> kin;
  Eigen::VectorXd start, goal;
  std::shared_ptr<runtime::Grid3> sdf;
  std::unique_ptr<runtime::TwoLayerChecker> checker;
  std::unique_ptr<runtime::ExactChecker> exact;
  double bake_seconds = 0;  // time spent building the distance field
};

// Reads a MoveIt PlanningScene YAML and MotionPlanRequest YAML (joint-space goal) for the robot.
// Joints the request sets outside the arm chain (fingers) keep the request's values.
ArmProblem load_arm_problem(const std::filesystem::path& robot_h5, const std::filesystem::path& scene_yaml,
                            const std::filesystem::path& request_yaml, const ArmProblemOptions& options = {});

struct PlanOutcome {
  bool solved = false;
  bool valid = false;        // every segment re-checked exactly at the resolution
  double seconds = 0;         // to the returned path
  double first_path_seconds = 0;  // to the first path, before shortcutting (= seconds for planners that do not shorten)
  double length = 0;         // joint-space path length
  runtime::JointPath path;
};

// Our planner: multi-goal RRT-Connect over the two-layer checker, single goal, one thread.
PlanOutcome plan_ours(const ArmProblem& p, double time_limit, double resolution, std::uint64_t seed);
// Marks out.path (from some planner) solved, measures its length and re-checks every segment with
// the exact layer at `resolution`: the one judge of every planner's path.
void judge_path(const ArmProblem& p, PlanOutcome& out, double resolution);

}  // namespace dmgplace::tools
