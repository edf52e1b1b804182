#pragma once
// An anytime multi-goal RRT-Connect (an ompl::base::Planner): one forward tree from the start, one
// backward tree per goal. Goals can be added and removed from another thread while solve() runs;
// when a backward tree connects, the path is reported at once (shortcut and re-validated) and
// planning continues toward the remaining goals.
#include <ompl/base/Planner.h>
#include <ompl/datastructures/NearestNeighbors.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <vector>

#include "dmgplace/runtime/types.hpp"

namespace dmgplace::runtime {

struct FoundPath {
  int goal_id = -1;
  JointPath path;         // start ... goal, every segment valid at the motion resolution
  double length = 0;      // joint-space length
  double time_found = 0;  // seconds since solve() started
  // When the trees met (or the straight line held), before shortcutting: the time OMPL's stock
  // planners report, since they do not shorten their paths.
  double time_connected = 0;
  std::size_t start_nodes = 0, goal_nodes = 0;  // the two trees' sizes when they met
};

class MultiGoalRRTConnect : public ompl::base::Planner {
 public:
  explicit MultiGoalRRTConnect(const ompl::base::SpaceInformationPtr& si);
  ~MultiGoalRRTConnect() override;

  // Thread-safe while solve() runs. A goal state must be valid; invalid goals are ignored
  // (reported by the return value).
  bool add_goal(int id, const std::vector<double>& q);
  void remove_goal(int id);
  std::size_t goal_count() const;
  // Paths found since the last call (thread-safe).
  std::vector<FoundPath> take_paths();
  // Goals whose path the validator refused since the last call (thread-safe): their trees are
  // gone, so the caller should stop counting them as open.
  std::vector<int> take_rejected();
  // Called (from the solving thread) for each path as soon as it is found.
  void set_path_callback(std::function<void(const FoundPath&)> cb) { callback_ = std::move(cb); }
  // Optional last word on a path before it is reported (e.g. an exact checker); false drops it.
  void set_path_validator(std::function<bool(const JointPath&)> v) { validator_ = std::move(v); }
  // A fixed extension range (joint-space length). Unset, the range is wide for the first
  // extensions and narrow after (setup()).
  void set_range(double r) { range_ = r; }
  void set_seed(std::uint64_t seed) { rng_.seed(seed); }
  // Another planner's start tree (same start, same joint space, another collision space: another
  // grasp), given before the first solve(): this planner's start tree begins as a copy of it, its
  // nodes unchecked here. A connection through them checks their edges in this planner's space
  // first, root down; a node that fails leaves the tree with everything grown from it. Paths
  // therefore stay valid in this space, while the tree's reach is another grasp's work.
  struct SeedNode {
    std::vector<double> q;
    std::size_t parent = 0;  // index of an earlier node; node 0 is the root (the start) and its parent unused
  };
  void seed_start_tree(std::vector<SeedNode> nodes);
  // The live nodes of the start tree, root first, parents before children (thread-safe while
  // solve() runs); empty before the first solve().
  std::vector<SeedNode> start_tree_snapshot() const;
  std::size_t start_tree_size() const;
  // Inherited nodes checked on the way to a connection, and those that failed (with their subtrees).
  std::size_t seeded_nodes_checked() const { return seeded_checked_; }
  std::size_t seeded_nodes_dropped() const { return seeded_dropped_; }

  // solve() keeps going after a connection until the condition says stop (anytime mode) or, when
  // false, returns after the first path (single-query mode).
  void set_anytime(bool anytime) { anytime_ = anytime; }

  ompl::base::PlannerStatus solve(const ompl::base::PlannerTerminationCondition& ptc) override;
  void clear() override;
  void setup() override;
  void getPlannerData(ompl::base::PlannerData& data) const override;

  struct Node;
  struct Tree;

 private:
  enum class Grow { Trapped, Advanced, Reached };
  Grow extend(Tree& tree, const std::vector<double>& target, Node*& added);
  Grow connect(Tree& tree, const std::vector<double>& target, Node*& added);
  void take_pending();
  FoundPath make_path(Node* from_start, Node* from_goal, int goal_id);
  void make_start_tree(const std::vector<double>& root);
  // Checks the unchecked (seeded) nodes between the root and `n`, root down; false when one fails
  // (it and its subtree are gone from the start tree).
  bool check_to_root(Node* n);
  void drop_subtree(Node* n);
  // Validator, callback, problem definition; false when the validator dropped the path.
  bool report(FoundPath f, std::chrono::steady_clock::time_point t0);
  // `ends_blocked`: the straight line from the first to the last waypoint is known to collide.
  void shortcut(JointPath& path, bool ends_blocked);
  // a is valid (a tree node); `b_valid`: so is b (CertifiedMotionValidator::checkMotionBetweenValid).
  bool motion_valid(const std::vector<double>& a, const std::vector<double>& b, bool b_valid = false) const;
  bool state_valid(const std::vector<double>& q) const;
  void sample(std::vector<double>& q);
  double distance(const std::vector<double>& a, const std::vector<double>& b) const;

  std::unique_ptr<Tree> start_tree_;
  mutable std::mutex start_mutex_;  // start_tree_'s nodes, for snapshots from other threads
  std::vector<SeedNode> seed_;
  std::atomic<std::size_t> seeded_checked_{0}, seeded_dropped_{0};
  std::map<int, std::unique_ptr<Tree>> goal_trees_;
  std::vector<int> untried_direct_;  // new goals whose straight line from the start is not tried yet
  std::set<int> blocked_direct_;     // goals whose straight line from the start collides
  mutable std::mutex mutex_;
  std::vector<std::pair<int, std::vector<double>>> pending_add_;
  std::vector<int> pending_remove_;
  std::vector<FoundPath> found_;
  std::vector<int> rejected_;
  std::function<void(const FoundPath&)> callback_;
  std::function<bool(const JointPath&)> validator_;
  std::mt19937_64 rng_{1};
  double range_ = 0;  // set_range's; 0: the wide-then-narrow schedule below
  double wide_range_ = 0, narrow_range_ = 0;
  long extensions_ = 0;  // since clear(): the schedule's clock
  bool anytime_ = true;
  std::size_t dim_ = 0;
  std::vector<double> lo_, hi_;
  mutable ompl::base::State* scratch_ = nullptr;  // owned; used by the solving thread only
  mutable ompl::base::State* scratch_end_ = nullptr;
};

}  // namespace dmgplace::runtime
