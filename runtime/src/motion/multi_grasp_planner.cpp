#include "dmgplace/runtime/motion/multi_grasp_planner.hpp"

#include "dmgplace/runtime/system/available_cpus.hpp"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>

#include <chrono>

namespace ob = ompl::base;

namespace dmgplace::runtime {

MultiGraspPlanner::MultiGraspPlanner(SpaceFactory factory, std::vector<double> start, int threads, std::uint64_t seed,
                                     double slice_seconds)
    : factory_(std::move(factory)), start_(std::move(start)), threads_(threads > 0 ? threads : available_cpus()),
      seed_(seed), slice_(slice_seconds) {}

MultiGraspPlanner::~MultiGraspPlanner() { stop(); }

MultiGraspPlanner::Entry& MultiGraspPlanner::entry(int grasp) {
  auto it = entries_.find(grasp);
  if (it != entries_.end()) return it->second;
  auto si = factory_(grasp);
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> s(si->getStateSpace());
  si->getStateSpace()->copyFromReals(s.get(), start_);
  pdef->addStartState(s);
  auto planner = std::make_shared<MultiGoalRRTConnect>(si);
  planner->setProblemDefinition(pdef);
  if (share_) {
    // The largest tree so far (the lowest grasp among equals: deterministic in synchronous mode).
    const MultiGoalRRTConnect* donor = nullptr;
    std::size_t most = 1;
    for (const auto& [g, e] : entries_)
      if (const std::size_t n = e.planner->start_tree_size(); n > most) most = n, donor = e.planner.get();
    if (donor) planner->seed_start_tree(donor->start_tree_snapshot());
  }
  planner->set_seed(seed_ + std::uint64_t(grasp) * 7919);
  planner->set_anytime(true);
  planner->setup();
  planner->set_path_validator([this, grasp](const JointPath& p) { return !validator_ || validator_(grasp, p); });
  return entries_[grasp] = Entry{planner, false};
}

bool MultiGraspPlanner::add_goal(int grasp, int goal_id, const std::vector<double>& q) {
  std::shared_ptr<MultiGoalRRTConnect> planner;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    planner = entry(grasp).planner;
  }
  return planner->add_goal(goal_id, q);
}

void MultiGraspPlanner::remove_goal(int grasp, int goal_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = entries_.find(grasp);
  if (it != entries_.end()) it->second.planner->remove_goal(goal_id);
}

std::pair<std::size_t, std::size_t> MultiGraspPlanner::seeded_nodes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::pair<std::size_t, std::size_t> out{0, 0};
  for (const auto& [g, e] : entries_) {
    out.first += e.planner->seeded_nodes_checked();
    out.second += e.planner->seeded_nodes_dropped();
  }
  return out;
}

std::vector<GraspPath> MultiGraspPlanner::take_paths() {
  std::lock_guard<std::mutex> lock(mutex_);
  collect_all();
  return std::exchange(found_, {});
}

std::vector<std::pair<int, int>> MultiGraspPlanner::take_rejected() {
  std::lock_guard<std::mutex> lock(mutex_);
  collect_all();
  return std::exchange(rejected_, {});
}

void MultiGraspPlanner::collect_all() {
  // A worker collects at the end of its slice; a path found inside one is taken at once (the
  // planners' own queues are thread-safe), not a slice later. Without workers, run_round has
  // collected everything already.
  if (!running_) return;
  for (auto& [grasp, e] : entries_) collect(grasp, *e.planner);
}

void MultiGraspPlanner::collect(int grasp, MultiGoalRRTConnect& planner) {
  for (auto& f : planner.take_paths()) found_.push_back({grasp, std::move(f)});
  for (int id : planner.take_rejected()) rejected_.emplace_back(grasp, id);
}

void MultiGraspPlanner::run_round(int iterations) {
  std::vector<std::pair<int, std::shared_ptr<MultiGoalRRTConnect>>> work;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& [grasp, e] : entries_)
      if (e.planner->goal_count() > 0) work.emplace_back(grasp, e.planner);
  }
  // The round's iterations are shared among the grasps with goals (each at least a few), so a
  // round costs about the same however many grasps wait: goal sampling, which runs between
  // rounds, keeps its share of the time as the asynchronous design intends.
  const int share = work.empty() ? 0 : std::max(kMinShare, iterations / int(work.size()));
  for (auto& [grasp, planner] : work) {
    auto left = std::make_shared<int>(share);
    // Stop early once its goals are all connected: an idle planner would only wait.
    auto* p = planner.get();
    planner->solve(ob::PlannerTerminationCondition([left, p] { return (*left)-- <= 0 || p->goal_count() == 0; }));
    std::lock_guard<std::mutex> lock(mutex_);
    collect(grasp, *planner);
  }
}

void MultiGraspPlanner::start() {
  if (running_.exchange(true)) return;
  for (int i = 0; i < threads_; ++i) workers_.emplace_back([this] { work(); });
}

void MultiGraspPlanner::stop() {
  running_ = false;
  for (auto& t : workers_) t.join();
  workers_.clear();
}

void MultiGraspPlanner::work() {
  while (running_) {
    int grasp = -1;
    std::shared_ptr<MultiGoalRRTConnect> planner;
    {
      // Round robin over grasps that have goals and no worker.
      std::lock_guard<std::mutex> lock(mutex_);
      const std::size_t n = entries_.size();
      for (std::size_t k = 0; k < n && !planner; ++k) {
        auto it = entries_.begin();
        std::advance(it, std::ptrdiff_t((turn_ + k) % n));
        if (!it->second.busy && it->second.planner->goal_count() > 0) {
          it->second.busy = true;
          grasp = it->first;
          planner = it->second.planner;
          turn_ = (turn_ + k + 1) % n;
        }
      }
    }
    if (!planner) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    // One slice, then the worker picks again so every grasp with goals gets served.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(slice_);
    planner->solve(ob::PlannerTerminationCondition(
        [this, deadline] { return !running_ || std::chrono::steady_clock::now() >= deadline; }));
    std::lock_guard<std::mutex> lock(mutex_);
    entries_[grasp].busy = false;
    collect(grasp, *planner);
  }
}

}  // namespace dmgplace::runtime
