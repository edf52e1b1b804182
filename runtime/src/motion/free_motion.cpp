#include "dmgplace/runtime/motion/free_motion.hpp"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>

#include <chrono>

#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"

namespace dmgplace::runtime {
namespace ob = ompl::base;

JointPath plan_free_motion(const Kinematics& kin, const ValidityFn& valid, const Eigen::VectorXd& from,
                           const Eigen::VectorXd& to, const MotionBudget& budget, MotionTree* tree) {
  if (!valid(from) || !valid(to)) return {};
  auto si = make_arm_space(kin, valid, budget.resolution);
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start(si->getStateSpace());
  for (int i = 0; i < kin.dof(); ++i) start[unsigned(i)] = from[i];
  pdef->addStartState(start);
  MultiGoalRRTConnect planner(si);
  planner.setProblemDefinition(pdef);
  planner.set_seed(budget.seed);
  planner.set_anytime(false);
  planner.setup();
  if (tree) planner.seed_start_tree(std::move(tree->nodes));
  if (!planner.add_goal(0, std::vector<double>(to.data(), to.data() + to.size()))) return {};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget.seconds);
  long polls = 0;
  // The iteration count ends the search first in practice, so the same inputs give the same path.
  planner.solve(ob::PlannerTerminationCondition(
      [&] { return ++polls > budget.iterations || std::chrono::steady_clock::now() >= deadline; }));
  if (tree) {
    auto left = planner.start_tree_snapshot();
    if (!left.empty()) {
      if (left.size() > MotionTree::kMaxNodes) left.resize(MotionTree::kMaxNodes);
      tree->nodes = std::move(left);
    }
  }
  auto paths = planner.take_paths();
  if (paths.empty()) return {};
  return std::move(paths.front().path);
}

}  // namespace dmgplace::runtime
