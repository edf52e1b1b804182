#include "stock_planner.hpp"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <chrono>

#include "dmgplace/runtime/motion/arm_space.hpp"

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace dmgplace::bench {

tools::PlanOutcome plan_stock(const tools::ArmProblem& p, const StockFclChecker& checker, double time_limit,
                              double resolution) {
  tools::PlanOutcome out;
  const auto t0 = std::chrono::steady_clock::now();
  auto si = runtime::make_arm_space(
      *p.kin, [&](const Eigen::VectorXd& q) { return checker.is_free(q); }, resolution);
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start(si->getStateSpace()), goal(si->getStateSpace());
  for (int i = 0; i < p.kin->dof(); ++i) {
    start[unsigned(i)] = p.start[i];
    goal[unsigned(i)] = p.goal[i];
  }
  pdef->setStartAndGoalStates(start, goal);
  og::RRTConnect planner(si);
  planner.setProblemDefinition(pdef);
  planner.setup();
  const auto status = planner.solve(ob::timedPlannerTerminationCondition(time_limit));
  out.seconds = out.first_path_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (status != ob::PlannerStatus::EXACT_SOLUTION) return out;
  auto* path = pdef->getSolutionPath()->as<og::PathGeometric>();
  for (std::size_t i = 0; i < path->getStateCount(); ++i) {
    std::vector<double> q;
    si->getStateSpace()->copyToReals(q, path->getState(i));
    out.path.push_back(q);
  }
  tools::judge_path(p, out, resolution);
  return out;
}

}  // namespace dmgplace::bench
