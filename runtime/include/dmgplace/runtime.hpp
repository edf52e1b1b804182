#pragma once
// dmgplace's embedding API: load the baked artifacts once, then ask placement, in-hand grasp and
// arm motion queries in your own process (C++; Python through the `dmgplace` module). No OMPL,
// FCL or Embree type appears in it. Units: metres and radians; poses are Eigen::Isometry3d,
// world frame = the robot base frame (z up); a grasp is the TCP pose in the object's frame.
//
//   auto world = dmgplace::World::load("arm.h5", "bottle.h5", "cabinet.h5");
//   dmgplace::runtime::PlacementQuery q;   // q0, g0, volume, objective, variant, seed, options
//   auto result = dmgplace::place(*world, q, dmgplace::stop_after_seconds(2),
//                                 [](const dmgplace::runtime::PlacementSolution& s) { /* each improvement */ });
//
// Contracts (as OMPL states them for its StateValidityChecker):
// - A World is immutable after load(): share one World between any number of threads and run
//   place(), reachable_grasps() and plan_motion() on it concurrently. Every query builds its own
//   per-query state (collision checkers, planner trees, random generators); nothing it does is
//   seen by another query. The World must outlive every query that uses it (hold the shared_ptr).
// - place() calls `stop` and `on_solution` on the calling thread only (with options.threads > 0,
//   planner workers run beside it, but callbacks are still made from the caller's thread). `stop`
//   is polled between search rounds, at least every few milliseconds of planning; returning true
//   ends the query within about one round. `on_solution` gets every strict improvement, in order.
// - With options.threads == 0 (the default) a query is deterministic: the same World, query and
//   seed give the same result, whatever else runs in the process.
// - Errors (bad artifacts, a query that does not fit the world) are dmgplace::Error, whose text
//   names the file or query element and the reason. Nothing is printed.
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/export.hpp"
#include "dmgplace/runtime/grasp/reachable_grasps.hpp"
#include "dmgplace/runtime/motion/trajectory.hpp"
#include "dmgplace/runtime/placement/placement_query.hpp"
#include "dmgplace/runtime/placement/placement_result.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/runtime/stop_condition.hpp"
#include "dmgplace/runtime/types.hpp"

namespace dmgplace {

namespace runtime {
class PlacementWorld;
}

class DMGPLACE_RUNTIME_EXPORT World {
 public:
  // Loads the three artifacts through the semantic gate (dmgplace::Error naming the file when one
  // is unsound) and builds every structure queries share. `finger_opening` (m, unset: the gripper's
  // maximum) is the finger joints' setting for the whole world; `joint_values` sets joints outside
  // the arm chain (another arm, a torso) by name, refusing names that are no such joint.
  static std::shared_ptr<const World> load(const std::filesystem::path& robot, const std::filesystem::path& object,
                                           const std::filesystem::path& environment,
                                           std::optional<double> finger_opening = std::nullopt,
                                           const std::map<std::string, double>& joint_values = {});
  // The same from artifacts already read (formats::load_*, which check them), e.g. to look at
  // the robot's joints before choosing `joint_values`.
  static std::shared_ptr<const World> from_artifacts(formats::RobotArtifact robot, formats::ObjectArtifact object,
                                                     formats::EnvironmentArtifact environment,
                                                     std::optional<double> finger_opening = std::nullopt,
                                                     const std::map<std::string, double>& joint_values = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  int dof() const;                                      // joints of the arm chain
  const std::vector<std::string>& joint_names() const;  // in the order of every q and JointPath
  Eigen::VectorXd lower_limits() const;
  Eigen::VectorXd upper_limits() const;
  Eigen::Isometry3d tcp_pose(const Eigen::VectorXd& q) const;  // forward kinematics of the chain's tip
  const runtime::Kinematics& kinematics() const;               // the arm chain (read-only)
  // How the three artifacts fit together: warnings only (what does not fit is refused by load):
  // `dmgplace validate --set` prints them.
  const std::vector<std::string>& fit_warnings() const;

 private:
  friend struct WorldAccess;  // the API's own functions reach the planner's world
  World();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

using runtime::stop_after_iterations;
using runtime::stop_after_seconds;
using runtime::StopCondition;  // runtime/stop_condition.hpp, with stop_after_seconds and stop_after_iterations
using SolutionCallback = std::function<void(const runtime::PlacementSolution&)>;

// The anytime placement search of Haustein, Cruciani et al. until `stop()` says so. q0 must be
// within the arm's limits; dmgplace::Error (naming query.source) when the query does not fit.
DMGPLACE_RUNTIME_EXPORT runtime::PlacementResult place(const World& world, const runtime::PlacementQuery& query,
                                                       const StopCondition& stop,
                                                       const SolutionCallback& on_solution = {});

// G(g0): every grasp reachable in-hand from the initial TCP pose `g0` (object frame), cheapest
// first, with the actions to each (ReachableGrasps::actions_to).
DMGPLACE_RUNTIME_EXPORT runtime::ReachableGrasps reachable_grasps(const World& world, const Eigen::Isometry3d& g0,
                                                                  std::optional<double> opening = std::nullopt);

// An arm motion query: from `start` to `goal` through the world's environment, holding the
// object at `grasp` (TCP in the object frame) or empty-handed.
struct MotionQuery {
  Eigen::VectorXd start, goal;             // arm chain joints, within limits
  std::optional<Eigen::Isometry3d> grasp;  // empty: empty-handed
  double time_limit = 1.0;                 // s, [0, 1e6]
  std::uint64_t seed = 1;
  double resolution = 0.05;       // joint-space collision check step (rad), [1e-4, 1]
  runtime::TimingOptions timing;  // the returned path's timing (velocity/acceleration scaling)
};

struct MotionResult {
  bool solved = false;
  runtime::JointPath path;         // start ... goal, every segment free at `resolution`
  runtime::Trajectory trajectory;  // `path` timed under the arm's limits (query.timing)
  double seconds = 0;              // planning and timing
  std::string reason;              // why not, when not solved
};

// Bidirectional RRT-Connect with the two-layer collision checker, shortcut, then timed
// (runtime/motion/trajectory.hpp). dmgplace::Error naming the field when the query is malformed.
DMGPLACE_RUNTIME_EXPORT MotionResult plan_motion(const World& world, const MotionQuery& query);

}  // namespace dmgplace
