#pragma once
// Serves one MultiGoalRRTConnect per grasp (each grasp its own collision space) with N worker
// threads: goals arrive and leave per grasp while the workers run; found paths are collected.
// With one thread and a fixed seed, the order of work is deterministic.
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"

namespace dmgplace::runtime {

struct GraspPath {
  int grasp = -1;
  FoundPath found;
};

class MultiGraspPlanner {
 public:
  // Builds the joint space (with the grasp's collision checker) for a grasp, once, on first use.
  using SpaceFactory = std::function<ompl::base::SpaceInformationPtr(int grasp)>;

  MultiGraspPlanner(SpaceFactory factory, std::vector<double> start, int threads = 0, std::uint64_t seed = 1,
                    double slice_seconds = 0.05);
  ~MultiGraspPlanner();
  MultiGraspPlanner(const MultiGraspPlanner&) = delete;
  MultiGraspPlanner& operator=(const MultiGraspPlanner&) = delete;

  // False when the goal is invalid in that grasp's space.
  bool add_goal(int grasp, int goal_id, const std::vector<double>& q);
  void remove_goal(int grasp, int goal_id);
  std::vector<GraspPath> take_paths();
  // (grasp, goal id) of goals whose path the validator refused since the last call.
  std::vector<std::pair<int, int>> take_rejected();
  // A grasp's planner, made at its first goal, starts from the largest start tree grown so far by
  // another grasp (MultiGoalRRTConnect::seed_start_tree: its nodes re-checked in the new grasp's
  // space on the way to a connection). On by default; set it before the first goal.
  void set_share_start_trees(bool share) { share_ = share; }
  // Over all grasps: seeded nodes checked on the way to a connection, and those dropped.
  std::pair<std::size_t, std::size_t> seeded_nodes() const;
  // Optional last check of every path of a grasp (e.g. the exact checker); set it before start().
  void set_path_validator(std::function<bool(int grasp, const JointPath&)> v) { validator_ = std::move(v); }

  // Synchronous and deterministic alternative to start(): serves every grasp with goals once, in
  // grasp order, on the calling thread, `iterations` planner iterations shared among them (at
  // least kMinShare each).
  void run_round(int iterations);
  static constexpr int kMinShare = 20;
  void start();
  void stop();  // joins the workers; also done by the destructor
  int threads() const { return threads_; }

 private:
  struct Entry {
    std::shared_ptr<MultiGoalRRTConnect> planner;
    bool busy = false;
  };
  Entry& entry(int grasp);                                // mutex_ held
  void collect(int grasp, MultiGoalRRTConnect& planner);  // mutex_ held
  void collect_all();                                     // mutex_ held
  void work();

  SpaceFactory factory_;
  std::vector<double> start_;
  int threads_;
  std::uint64_t seed_;
  double slice_;
  bool share_ = true;
  std::function<bool(int, const JointPath&)> validator_;
  mutable std::mutex mutex_;
  std::map<int, Entry> entries_;
  std::size_t turn_ = 0;
  std::vector<GraspPath> found_;
  std::vector<std::pair<int, int>> rejected_;
  std::vector<std::thread> workers_;
  std::atomic<bool> running_{false};
};

}  // namespace dmgplace::runtime
