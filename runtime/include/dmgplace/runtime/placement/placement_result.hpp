#pragma once
// What a placement query returns: every improvement found (pose, grasp g*, in-hand actions from
// g0, arm path, retreat), a trace of the best objective over time and the search's counters. Plain
// values: no planning library type, safe to copy across threads.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "dmgplace/runtime/grasp/reachable_grasps.hpp"
#include "dmgplace/runtime/motion/trajectory.hpp"
#include "dmgplace/runtime/types.hpp"

namespace dmgplace::runtime {

// Said wherever a solution's in-hand actions are reported: the pushes are planned in the object
// (the DMG), not for a robot that performs them.
inline constexpr const char* kInHandExecutionNote =
    "the in-hand actions are the DMG's pushes and rotations of the object in the closed gripper; they need a second "
    "arm or a fixture to push the object (as the paper executes them), which dmgplace does not plan: no pusher "
    "trajectory is given";

// Said instead when the pushes are planned for the query's pusher arm.
inline constexpr const char* kInHandPlannedNote =
    "the in-hand actions are performed by the pusher arm while the grasping arm holds q0: see pushes (one timed "
    "trajectory of the pusher per action)";

// One in-hand action as the pusher performs it (the grasping arm at q0): from its start
// configuration to a pre-push pose `standoff` from the object, in to the contact, the push (the
// contact moving with the object), back out along the push, and home again.
struct PushPlan {
  int action = 0;                                       // index in PlacementSolution::in_hand
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();    // world: where the tool touches the object
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // world, unit: the tool's push at the contact
  Eigen::Isometry3d object_before = Eigen::Isometry3d::Identity(),
                    object_after = Eigen::Isometry3d::Identity();  // world
  Eigen::Isometry3d grasp_after = Eigen::Isometry3d::Identity();   // TCP in the object frame after the action
  JointPath path;                    // the pusher's joints (PlacementResult::pusher_joints)
  int push_begin = 0, push_end = 0;  // waypoints of `path` in contact with the object: [push_begin, push_end]
  Trajectory trajectory;             // `path` timed under the pusher's limits
};

struct PlacementCounters {
  long iterations = 0;     // outer loop rounds
  long samples = 0;        // poses sampled by MCTS rollouts
  long stable = 0;         // ... of which stable on their region
  long object_free = 0;    // ... and with the object free of the scene
  long improving = 0;      // ... and improving on the best so far
  long cached_grasps = 0;  // samples whose grasp came from Algorithm 3's cache
  long ik_calls = 0, ik_solutions = 0;
  long reachable = 0;         // IK solutions free of collision: kinematically reachable samples
  long collision_checks = 0;  // arm configurations checked (fast layer; exact where needed)
  long exact_checks = 0;      // of which needed FCL
  long object_checks = 0;     // object-alone checks of sampled poses
  long hand_checks = 0;       // hand-only grasp filter checks
  long goals = 0;             // valid goals handed to the motion planner
  long planner_calls = 0;     // planner rounds (synchronous) or polls (threaded)
  long paths = 0;             // paths the motion planner returned
  long paths_rejected = 0;    // arm paths the exact re-check refused (their goals are dropped)
  long seeded_checked = 0;    // start-tree nodes shared from another grasp and checked for this one
  long seeded_dropped = 0;    // ... and the nodes dropped with them (invalid for this grasp)
  long retreat_failures = 0;  // reached placements dropped because the hand could not withdraw
  long push_failures = 0;     // grasps left out because the pusher could not perform an action to them
  long push_plans = 0;        // in-hand actions planned for the pusher (each once per run)
  double push_seconds = 0;    // time spent planning them (s)
};

struct PlacementSolution {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // object resting on the support (world)
  double objective = 0;
  int face = -1, region = -1;  // object placement face; region index in the environment artifact
  int grasp_state = -1;        // grasp-graph state of g*
  Eigen::Isometry3d grasp = Eigen::Isometry3d::Identity();  // g*: TCP in the object frame
  double opening = 0;
  double grasp_cost = 0;              // in-hand path cost from g0
  std::vector<InHandAction> in_hand;  // g0 -> g*
  JointPath path;                     // q0 ... placement configuration (object held `lift` above its resting pose)
  JointPath retreat;                  // placement configuration ... retreat configuration (empty when not checked)
  double release_opening = 0;         // m: the fingers open this far to let go (the retreat is checked so)
  Trajectory trajectory;              // `path` timed under the arm's limits (options' scaling)
  Trajectory retreat_trajectory;      // `retreat` timed the same way (empty when it is)
  std::vector<PushPlan> pushes;       // one per in_hand action when the query has a pusher
  double time = 0;                    // seconds since run() started
  PlacementCounters counters;
};

struct TracePoint {
  double time = 0;
  double best = 0;  // NaN before the first solution
  PlacementCounters counters;
};

struct PlacementResult {
  std::vector<PlacementSolution> improvements;  // in the order found; the last is the best
  std::vector<TracePoint> trace;                // one point per improvement and at least every 0.1 s
  PlacementCounters counters;
  double seconds = 0;
  int reachable_grasps = 0;
  int initial_state = -1;                  // the grasp-graph state nearest g0: in-hand sequences start there
  double snap_distance = 0;                // how far g0 is from it (GraspGraph::snap's score: m + 0.05 m/rad)
  double initial_opening = 0;              // g0's finger opening (given, or measured on the object's mesh)
  std::vector<std::string> pusher_joints;  // the pusher's joints, PushPlan::path's order (empty: no pusher)
  std::string reason;                      // why there is no solution (empty when there is one)
  bool solved() const { return !improvements.empty(); }
  const PlacementSolution& best() const { return improvements.back(); }
};

}  // namespace dmgplace::runtime
