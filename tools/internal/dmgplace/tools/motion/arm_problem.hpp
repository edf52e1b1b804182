#pragma once
// One arm motion-planning problem made ready to solve: robot, scene, start and goal, the fast
// collision layer (over the scene's primitives, or a workspace distance field) and the exact one.
// The robot's part of both is built once (ArmRobot) and shared by every scene's problem.
#include <filesystem>
#include <memory>
#include <optional>

#include "dmgplace/formats/environment_artifact.hpp"
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
  // A scene of at most 64 exact primitives is checked against them alone, with no field baked;
  // true bakes the field anyway (the checks then read it nowhere: for comparing setup costs).
  bool always_field = false;
};

// A robot ready for many scenes: its artifact, kinematics, and the scene-independent parts of its
// checkers (sphere bodies, link geometry), built once.
struct ArmRobot {
  formats::RobotArtifact robot;
  std::unique_ptr<runtime::Kinematics> kin;
  std::unique_ptr<runtime::SphereFieldChecker> fast;  // no field, no scene yet
  std::unique_ptr<runtime::ExactChecker> exact;       // an empty scene
};
std::shared_ptr<const ArmRobot> load_arm_robot(const std::filesystem::path& robot_h5);

struct ArmProblem {
  std::shared_ptr<const ArmRobot> robot;
  Scene scene;
  std::unique_ptr<runtime::Kinematics> kin;  // the robot's, with the request's finger values
  Eigen::VectorXd start, goal;
  std::shared_ptr<runtime::Grid3> sdf;  // null where the scene's primitives serve instead
  std::unique_ptr<runtime::TwoLayerChecker> checker;
  std::unique_ptr<runtime::ExactChecker> exact;
  double bake_seconds = 0;   // time spent building the distance field (0: none built)
  double setup_seconds = 0;  // everything the scene needs before planning: field (if any) and checkers
};

// Reads a MoveIt PlanningScene YAML and MotionPlanRequest YAML (joint-space goal) for the robot.
// Joints the request sets outside the arm chain (fingers) keep the request's values.
ArmProblem load_arm_problem(std::shared_ptr<const ArmRobot> robot, const std::filesystem::path& scene_yaml,
                            const std::filesystem::path& request_yaml, const ArmProblemOptions& options = {});
ArmProblem load_arm_problem(const std::filesystem::path& robot_h5, const std::filesystem::path& scene_yaml,
                            const std::filesystem::path& request_yaml, const ArmProblemOptions& options = {});

// The robot in a baked environment (ENV.h5: an Embree distance field over meshes or a scan), checked
// as placement queries check it; start and goal are left for the caller to set.
ArmProblem arm_problem_in_environment(std::shared_ptr<const ArmRobot> robot, const formats::EnvironmentArtifact& env);

struct PlanOutcome {
  bool solved = false;
  bool valid = false;             // every segment re-checked exactly at the resolution
  double seconds = 0;             // to the returned path
  double first_path_seconds = 0;  // to the first path, before shortcutting (= seconds for planners that do not shorten)
  double planner_setup_seconds = 0;  // of both: the space, the planner and its goal, before planning
  double length = 0;                 // joint-space path length
  runtime::JointPath path;
};

// Our planner: multi-goal RRT-Connect over the two-layer checker, single goal, one thread.
PlanOutcome plan_ours(const ArmProblem& p, double time_limit, double resolution, std::uint64_t seed);
// Marks out.path (from some planner) solved, measures its length and re-checks every segment with
// the exact layer at `resolution`: the one judge of every planner's path.
void judge_path(const ArmProblem& p, PlanOutcome& out, double resolution);

}  // namespace dmgplace::tools
