#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"
#include "dmgplace/runtime/motion/nearest_states.hpp"
#include "dmgplace/runtime/motion/certified_motion_validator.hpp"

#include <ompl/base/PlannerData.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

namespace ob = ompl::base;

namespace dmgplace::runtime {

struct MultiGoalRRTConnect::Node {
  std::vector<double> q;
  Node* parent = nullptr;
  std::size_t index = 0;  // in Tree::nodes and its nn
  bool checked = true;    // the state and the edge from parent are valid in this planner's space
  bool dropped = false;   // out of the tree (a seeded ancestor failed)
};

struct MultiGoalRRTConnect::Tree {
  std::vector<std::unique_ptr<Node>> nodes;  // parents before children
  NearestStates nn;                          // nodes[i] is point i
  std::mutex* guard = nullptr;               // the start tree's, held while it changes
  explicit Tree(std::size_t dim, std::mutex* g = nullptr) : nn(dim), guard(g) {}
  Node* add(std::vector<double> q, Node* parent, bool checked = true) {
    std::unique_lock<std::mutex> lock;
    if (guard) lock = std::unique_lock<std::mutex>(*guard);
    nn.add(q.data());
    nodes.push_back(std::make_unique<Node>(Node{std::move(q), parent, nodes.size(), checked, false}));
    return nodes.back().get();
  }
  Node* nearest(const std::vector<double>& q) const { return nodes[nn.nearest(q.data())].get(); }
};

MultiGoalRRTConnect::MultiGoalRRTConnect(const ob::SpaceInformationPtr& si) : ob::Planner(si, "MultiGoalRRTConnect") {
  specs_.multithreaded = false;
  specs_.directed = false;
}

namespace {
// The default range schedule (setup()): fractions of the space's maximum extent, and how many
// extensions take the wide one. Chosen on MotionBenchMaker's two shared Panda sets; their
// neighbours (10-12%, 4-6%, 50-300 extensions) did about as well, and every fixed range had a
// longer tail (docs/motion.md, "Extension range").
constexpr double kWideRange = 0.11, kNarrowRange = 0.05;
constexpr long kWideExtensions = 100;
}  // namespace

MultiGoalRRTConnect::~MultiGoalRRTConnect() {
  if (scratch_) si_->freeState(scratch_);
  if (scratch_end_) si_->freeState(scratch_end_);
}

void MultiGoalRRTConnect::setup() {
  ob::Planner::setup();
  dim_ = si_->getStateDimension();
  auto* rv = si_->getStateSpace()->as<ob::RealVectorStateSpace>();
  lo_ = rv->getBounds().low;
  hi_ = rv->getBounds().high;
  // Without a set range (OMPL's RRTConnect uses 20% of the extent): 11% for the first 100
  // extensions, then 5%. Most problems are solved within the first, where long extensions reach
  // far for few certified checks; a problem still open after them has narrow passages (shelves),
  // where long extensions mostly fail or cost many checks. On MotionBenchMaker any fixed range
  // trades one for the other (short ranges a slower median, long ones a longer tail); the
  // schedule has both (docs/motion.md).
  const double extent = si_->getMaximumExtent();
  wide_range_ = range_ > 0 ? range_ : kWideRange * extent;
  narrow_range_ = range_ > 0 ? range_ : kNarrowRange * extent;
}

void MultiGoalRRTConnect::clear() {
  ob::Planner::clear();
  extensions_ = 0;
  {
    std::lock_guard<std::mutex> lock(start_mutex_);
    start_tree_.reset();
  }
  seed_.clear();
  seeded_checked_ = seeded_dropped_ = 0;
  std::lock_guard<std::mutex> lock(mutex_);
  goal_trees_.clear();
  pending_add_.clear();
  pending_remove_.clear();
  found_.clear();
  rejected_.clear();
  blocked_direct_.clear();
}

double MultiGoalRRTConnect::distance(const std::vector<double>& a, const std::vector<double>& b) const {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s);
}

bool MultiGoalRRTConnect::state_valid(const std::vector<double>& q) const {
  // The solving thread's scratch state; only one thread solves a planner at a time.
  if (!scratch_) scratch_ = si_->allocState();
  si_->getStateSpace()->copyFromReals(scratch_, q);
  return si_->isValid(scratch_);
}

bool MultiGoalRRTConnect::motion_valid(const std::vector<double>& a, const std::vector<double>& b, bool b_valid) const {
  // The space's motion validator: OMPL's discrete one (bisection order, every longest-valid-segment
  // step) unless the space has a certified one (make_arm_space with a free-distance function).
  if (!scratch_) scratch_ = si_->allocState();
  if (!scratch_end_) scratch_end_ = si_->allocState();
  si_->getStateSpace()->copyFromReals(scratch_, a);
  si_->getStateSpace()->copyFromReals(scratch_end_, b);
  // Both ends tree nodes (a shortcut jump, a new goal's straight line from the start): no far end
  // checked first (identical answers in less time).
  if (b_valid)
    if (const auto* v = dynamic_cast<const CertifiedMotionValidator*>(si_->getMotionValidator().get()))
      return v->checkMotionBetweenValid(scratch_, scratch_end_);
  return si_->checkMotion(scratch_, scratch_end_);
}

void MultiGoalRRTConnect::sample(std::vector<double>& q) {
  q.resize(dim_);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t k = 0; k < dim_; ++k) q[k] = lo_[k] + u(rng_) * (hi_[k] - lo_[k]);
}

MultiGoalRRTConnect::Grow MultiGoalRRTConnect::extend(Tree& tree, const std::vector<double>& target, Node*& added) {
  Node* near = tree.nearest(target);
  const double d = distance(near->q, target);
  std::vector<double> q = target;
  bool reached = true;
  const double range = extensions_++ < kWideExtensions ? wide_range_ : narrow_range_;
  if (d > range) {
    for (std::size_t k = 0; k < q.size(); ++k) q[k] = near->q[k] + (target[k] - near->q[k]) * (range / d);
    reached = false;
  }
  if (!motion_valid(near->q, q)) return Grow::Trapped;
  added = tree.add(std::move(q), near);
  return reached ? Grow::Reached : Grow::Advanced;
}

MultiGoalRRTConnect::Grow MultiGoalRRTConnect::connect(Tree& tree, const std::vector<double>& target, Node*& added) {
  Grow g;
  do g = extend(tree, target, added);
  while (g == Grow::Advanced);
  return g;
}

bool MultiGoalRRTConnect::add_goal(int id, const std::vector<double>& q) {
  if (q.size() != si_->getStateDimension()) return false;
  // Called from other threads while solve() runs: a state of its own, not the solver's scratch.
  ob::State* s = si_->allocState();
  si_->getStateSpace()->copyFromReals(s, q);
  const bool valid = si_->isValid(s);
  si_->freeState(s);
  if (!valid) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  pending_add_.emplace_back(id, q);
  return true;
}

void MultiGoalRRTConnect::remove_goal(int id) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_remove_.push_back(id);
  pending_add_.erase(std::remove_if(pending_add_.begin(), pending_add_.end(), [&](auto& p) { return p.first == id; }),
                     pending_add_.end());
}

std::size_t MultiGoalRRTConnect::goal_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return goal_trees_.size() + pending_add_.size();
}

std::vector<FoundPath> MultiGoalRRTConnect::take_paths() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(found_, {});
}

std::vector<int> MultiGoalRRTConnect::take_rejected() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(rejected_, {});
}

void MultiGoalRRTConnect::take_pending() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& [id, q] : pending_add_) {
    auto t = std::make_unique<Tree>(si_->getStateDimension());
    t->add(q, nullptr);
    goal_trees_[id] = std::move(t);
    untried_direct_.push_back(id);
    blocked_direct_.erase(id);  // (an id may come back with another configuration)
  }
  pending_add_.clear();
  for (int id : pending_remove_) goal_trees_.erase(id);
  pending_remove_.clear();
}

void MultiGoalRRTConnect::shortcut(JointPath& path, bool ends_blocked) {
  // Greedy and deterministic: from each waypoint, jump to the farthest later one it sees. Blocked
  // jumps fail after a few checks (bisection order), and no pair is ever tried twice (nor the
  // straight start-goal line, when that was tried before the trees grew).
  int budget = 100;
  for (std::size_t i = 0; i + 2 < path.size() && budget > 0; ++i)
    for (std::size_t j = path.size() - 1; j >= i + 2 && budget > 0; --j, --budget)
      if (!(ends_blocked && i == 0 && j == path.size() - 1) && motion_valid(path[i], path[j], true)) {
        path.erase(path.begin() + std::ptrdiff_t(i) + 1, path.begin() + std::ptrdiff_t(j));
        break;
      }
}

void MultiGoalRRTConnect::seed_start_tree(std::vector<SeedNode> nodes) { seed_ = std::move(nodes); }

void MultiGoalRRTConnect::make_start_tree(const std::vector<double>& root) {
  auto tree = std::make_unique<Tree>(si_->getStateDimension(), &start_mutex_);
  tree->add(root, nullptr);
  // A seed from another start counts for nothing: its paths would not begin here.
  if (!seed_.empty() && seed_.front().q == root)
    for (std::size_t i = 1; i < seed_.size(); ++i)
      if (seed_[i].parent < i) tree->add(seed_[i].q, tree->nodes[seed_[i].parent].get(), false);
  seed_.clear();
  std::lock_guard<std::mutex> lock(start_mutex_);
  start_tree_ = std::move(tree);
}

std::vector<MultiGoalRRTConnect::SeedNode> MultiGoalRRTConnect::start_tree_snapshot() const {
  std::lock_guard<std::mutex> lock(start_mutex_);
  std::vector<SeedNode> out;
  if (!start_tree_) return out;
  std::vector<std::size_t> renumber(start_tree_->nodes.size());
  for (const auto& n : start_tree_->nodes) {
    if (n->dropped) continue;
    renumber[n->index] = out.size();
    out.push_back({n->q, n->parent ? renumber[n->parent->index] : 0});
  }
  return out;
}

std::size_t MultiGoalRRTConnect::start_tree_size() const {
  std::lock_guard<std::mutex> lock(start_mutex_);
  return start_tree_ ? start_tree_->nodes.size() : 0;
}

bool MultiGoalRRTConnect::check_to_root(Node* n) {
  std::vector<Node*> unchecked;
  for (Node* m = n; m; m = m->parent)
    if (!m->checked) unchecked.push_back(m);
  for (auto it = unchecked.rbegin(); it != unchecked.rend(); ++it) {
    Node* m = *it;
    ++seeded_checked_;
    // The parent is valid here (checked, or checked just before): OMPL's checkMotion contract.
    if (!motion_valid(m->parent->q, m->q)) {
      drop_subtree(m);
      return false;
    }
    m->checked = true;
  }
  return true;
}

void MultiGoalRRTConnect::drop_subtree(Node* n) {
  // Parents come before children, so one pass from n marks its whole subtree.
  std::lock_guard<std::mutex> lock(start_mutex_);
  auto& nodes = start_tree_->nodes;
  for (std::size_t i = n->index; i < nodes.size(); ++i) {
    Node* m = nodes[i].get();
    if (m->dropped || !(m == n || (m->parent && m->parent->dropped))) continue;
    m->dropped = true;
    start_tree_->nn.remove(i);
    ++seeded_dropped_;
  }
}

FoundPath MultiGoalRRTConnect::make_path(Node* a, Node* b, int goal_id) {
  FoundPath f;
  f.goal_id = goal_id;
  for (Node* n = a; n; n = n->parent) f.path.push_back(n->q);
  std::reverse(f.path.begin(), f.path.end());
  for (Node* n = b; n; n = n->parent)
    if (distance(n->q, f.path.back()) > 1e-12) f.path.push_back(n->q);
  shortcut(f.path, blocked_direct_.count(goal_id) > 0);  // (a path always runs root to root)
  for (std::size_t i = 1; i < f.path.size(); ++i) f.length += distance(f.path[i - 1], f.path[i]);
  return f;
}

ob::PlannerStatus MultiGoalRRTConnect::solve(const ob::PlannerTerminationCondition& ptc) {
  // Goals come through add_goal(), not the problem definition: only a start is required.
  if (!pdef_ || pdef_->getStartStateCount() == 0) return ob::PlannerStatus::INVALID_START;
  const auto t0 = std::chrono::steady_clock::now();
  if (!start_tree_) {
    const ob::State* st = pis_.nextStart();
    if (!st) return ob::PlannerStatus::INVALID_START;
    std::vector<double> q;
    si_->getStateSpace()->copyToReals(q, st);
    if (!state_valid(q)) return ob::PlannerStatus::INVALID_START;
    make_start_tree(q);
  }
  std::vector<double> q_rand;
  std::size_t turn = 0;
  bool solved = false;
  while (!ptc) {
    take_pending();
    if (goal_trees_.empty()) {
      if (!anytime_ && solved) break;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    Node *from_start = nullptr, *from_goal = nullptr;  // the two ends of a connection
    int goal_id = -1;
    if (!untried_direct_.empty()) {
      // A new goal first tries the straight line from the start: often free, and then no tree grows.
      goal_id = untried_direct_.back();
      untried_direct_.pop_back();
      auto g = goal_trees_.find(goal_id);
      if (g == goal_trees_.end()) continue;
      from_start = start_tree_->nodes.front().get();
      from_goal = g->second->nodes.front().get();
      if (!motion_valid(from_start->q, from_goal->q, true)) {
        blocked_direct_.insert(goal_id);
        continue;
      }
    } else {
      sample(q_rand);
      // Pick one goal tree per iteration, round robin, so every goal gets attention.
      auto it = goal_trees_.begin();
      std::advance(it, std::ptrdiff_t(turn++ % goal_trees_.size()));
      goal_id = it->first;
      Tree& goal = *it->second;
      // The smaller tree grows toward the sample, the other connects (balanced RRT-Connect):
      // where one end sits in a narrow pocket (a goal deep in a shelf or a cage) its tree grows
      // slowly, and alternating would spend half the extensions on the other tree's open side
      // (faster on every MotionBenchMaker Panda set, the tail most: docs/perf-log.md).
      const bool forward = start_tree_->nodes.size() <= goal.nodes.size();
      Tree& grow = forward ? *start_tree_ : goal;
      Tree& other = forward ? goal : *start_tree_;
      Node* a = nullptr;
      if (extend(grow, q_rand, a) == Grow::Trapped) continue;
      Node* b = nullptr;
      if (connect(other, a->q, b) != Grow::Reached) continue;
      from_start = forward ? a : b;
      from_goal = forward ? b : a;
    }
    if (!check_to_root(from_start)) continue;
    const double connected = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    FoundPath f = make_path(from_start, from_goal, goal_id);
    f.time_connected = connected;
    f.start_nodes = start_tree_->nodes.size();
    f.goal_nodes = goal_trees_.at(goal_id)->nodes.size();
    {
      // Writers hold the mutex: goal_count() reads the map from other threads.
      std::lock_guard<std::mutex> lock(mutex_);
      goal_trees_.erase(goal_id);  // reported once; the caller decides what to add next
    }
    if (!report(std::move(f), t0)) continue;
    solved = true;
    if (!anytime_) break;
  }
  return solved ? ob::PlannerStatus::EXACT_SOLUTION : ob::PlannerStatus::TIMEOUT;
}

bool MultiGoalRRTConnect::report(FoundPath f, std::chrono::steady_clock::time_point t0) {
  f.time_found = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (validator_ && !validator_(f.path)) {
    std::lock_guard<std::mutex> lock(mutex_);
    rejected_.push_back(f.goal_id);
    return false;
  }
  if (callback_) callback_(f);
  if (pdef_) {
    auto path = std::make_shared<ompl::geometric::PathGeometric>(si_);
    ob::State* s = si_->allocState();
    for (const auto& q : f.path) {
      si_->getStateSpace()->copyFromReals(s, q);
      path->append(s);
    }
    si_->freeState(s);
    pdef_->addSolutionPath(path, false, 0.0, getName());
  }
  std::lock_guard<std::mutex> lock(mutex_);
  found_.push_back(std::move(f));
  return true;
}

void MultiGoalRRTConnect::getPlannerData(ob::PlannerData& data) const {
  ob::Planner::getPlannerData(data);
  if (!start_tree_) return;
  ob::State* s = si_->allocState();
  for (const auto& n : start_tree_->nodes) {
    if (n->dropped) continue;
    si_->getStateSpace()->copyFromReals(s, n->q);
    data.addVertex(ob::PlannerDataVertex(s));
  }
  si_->freeState(s);
}

}  // namespace dmgplace::runtime
