#pragma once
// The in-hand actions planned for a second arm, as the paper executes them: the grasping arm holds
// q0, the pusher's tool moves to a pose `standoff` in front of a contact on the object (a free
// motion), in to the contact, pushes while the contact moves with the object (a Cartesian path,
// each step solved by IK), backs out along the push and returns to its start (a free motion).
//
// What is checked (exact, FCL), the grasping arm at q0 and its fingers at the grasp's opening:
// every pusher state against the scene and against the whole robot (the grasping arm, its hand
// and fingers, the pusher itself: the SRDF's allowed pairs apart); against the object at its pose
// before the action up to the push's midpoint and after it from there, where only the pusher's
// tool (tool_links(): the links rigid with its TCP) may touch it, and only from half the standoff
// before the contact to half the standoff after the push; every segment at the motion resolution.
// The object's own sweep through the push is not checked against the scene: it moves within the
// closed gripper.
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "dmgplace/runtime/motion/arm_timing.hpp"
#include "dmgplace/runtime/motion/free_motion.hpp"
#include "dmgplace/runtime/placement/placement_query.hpp"
#include "dmgplace/runtime/placement/placement_result.hpp"
#include "dmgplace/runtime/placement/placement_world.hpp"

namespace dmgplace::runtime {

struct PushWaypoint;

class PushPlanner {
 public:
  // Checks `spec` against the world (dmgplace::Error naming `source` and the pusher element):
  // the chain exists and descends from the grasping arm's base with no moving joint before its
  // own base, shares no joint with the grasping arm, and starts (its joints' values in the world)
  // within its limits and free of collision with the grasping arm at q0.
  PushPlanner(const PlacementWorld& world, const PusherSpec& spec, const Eigen::VectorXd& q0, double resolution,
              std::uint64_t seed, const std::string& source);
  ~PushPlanner();

  const Kinematics& kinematics() const { return *kin_; }
  const Eigen::VectorXd& start() const { return start_; }
  const std::vector<int>& tool_links() const { return tool_; }
  // The pusher's TCP in the world at pusher configuration q.
  Eigen::Isometry3d tcp_pose(const Eigen::VectorXd& q) const { return kin_->tip_pose(q) * spec_.tcp; }

  // Every action of `actions` (consecutive, from g0's DMG state) planned, or nullopt when one
  // cannot be: then the grasp they lead to is out of reach. Each action is planned once per
  // planner (cached by its two grasp states). Thread-safe.
  std::optional<std::vector<PushPlan>> plan(const std::vector<InHandAction>& actions, const TimingOptions& timing);
  long planned() const;    // actions planned so far (cache misses)
  double seconds() const;  // time spent planning them

 private:
  std::optional<PushPlan> plan_action(const InHandAction& a);
  // IK along the TCP waypoints (from the start configuration, then each from the last), every
  // state and segment valid under its waypoint's checker; empty where a step fails or jumps.
  JointPath cartesian_path(const std::vector<PushWaypoint>& way, const Kinematics& kin, std::mt19937_64& rng) const;
  const PlacementWorld& world_;
  PusherSpec spec_;
  Eigen::VectorXd q0_;
  double resolution_;
  std::uint64_t seed_;
  std::unique_ptr<Kinematics> kin_;
  std::unique_ptr<ExactChecker> exact_;
  // The free motions' tree from the pusher's start, grown on by every action's moves (both are
  // planned from the start: the move back is planned out and reversed).
  std::mutex tree_mutex_;
  MotionTree tree_;
  Eigen::VectorXd start_;
  std::vector<int> tool_;
  double contact_spacing_ = 0;  // m between candidate contacts: a share of the object's size
  mutable std::mutex mutex_;
  std::map<std::pair<int, int>, std::optional<PushPlan>> cache_;
  long planned_ = 0;
  double seconds_ = 0;
};

}  // namespace dmgplace::runtime
