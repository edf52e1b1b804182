#include "dmgplace/runtime/placement/retreat_motion.hpp"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>

#include <chrono>

#include "dmgplace/runtime/motion/segment_check.hpp"

#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"

namespace dmgplace::runtime {
namespace ob = ompl::base;

bool retreat_state_free(const RetreatScene& s, const Eigen::VectorXd& q) {
  if (!s.arm->is_free(q)) return false;
  thread_local std::vector<Eigen::Isometry3d> poses;
  s.kin->link_poses(q, poses);
  for (const auto& sp : *s.spheres) {
    const Eigen::Vector3d c = poses[std::size_t(sp.link)] * sp.center;
    // A sphere clear of the object's ball keeps its part of the link clear of the object.
    if ((c - s.object_center).norm() < sp.radius + s.object_radius) return s.placed->is_free(q);
  }
  return true;
}

JointPath retrace_approach(const RetreatScene& s, const Eigen::VectorXd& from, const JointPath& approach,
                           double resolution) {
  if (approach.empty()) return {};
  const ValidityFn valid = [&s](const Eigen::VectorXd& q) { return retreat_state_free(s, q); };
  const auto vec = [](const std::vector<double>& v) { return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size())); };
  // back_free: how many of the approach's first waypoints lead back to its start, every segment free.
  std::size_t back_free = 0;
  if (valid(vec(approach[0]))) {
    back_free = 1;
    while (back_free < approach.size() && segment_valid(vec(approach[back_free]), vec(approach[back_free - 1]), resolution, valid))
      ++back_free;
  }
  for (std::size_t j = back_free; j-- > 0;) {
    if (!segment_valid(from, vec(approach[j]), resolution, valid)) continue;
    JointPath out{std::vector<double>(from.data(), from.data() + from.size())};
    for (std::size_t k = j + 1; k-- > 0;) out.push_back(approach[k]);
    return out;
  }
  return {};
}

JointPath plan_retreat_motion(const RetreatScene& s, const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                              const RetreatBudget& budget) {
  const auto valid = [&s](const Eigen::VectorXd& q) { return retreat_state_free(s, q); };
  if (!valid(from) || !valid(to)) return {};
  auto si = make_arm_space(*s.kin, valid, budget.resolution);
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start(si->getStateSpace());
  for (int i = 0; i < s.kin->dof(); ++i) start[unsigned(i)] = from[i];
  pdef->addStartState(start);
  MultiGoalRRTConnect planner(si);
  planner.setProblemDefinition(pdef);
  planner.set_seed(budget.seed);
  planner.set_anytime(false);
  planner.setup();
  if (!planner.add_goal(0, std::vector<double>(to.data(), to.data() + to.size()))) return {};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget.seconds);
  long polls = 0;
  // The iteration count ends the search first in practice, so the same inputs give the same path.
  planner.solve(ob::PlannerTerminationCondition(
      [&] { return ++polls > budget.iterations || std::chrono::steady_clock::now() >= deadline; }));
  auto paths = planner.take_paths();
  if (paths.empty()) return {};
  return std::move(paths.front().path);
}

}  // namespace dmgplace::runtime
