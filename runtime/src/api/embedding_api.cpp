#include "dmgplace/runtime.hpp"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>

#include <chrono>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"

namespace dmgplace {
namespace ob = ompl::base;

struct World::Impl {
  std::unique_ptr<runtime::PlacementWorld> world;
};

World::World() : impl_(std::make_unique<Impl>()) {}
World::~World() = default;

std::shared_ptr<const World> World::load(const std::filesystem::path& robot, const std::filesystem::path& object,
                                         const std::filesystem::path& environment, double finger_opening,
                                         const std::map<std::string, double>& joint_values) {
  std::shared_ptr<World> w(new World());
  w->impl_->world = std::make_unique<runtime::PlacementWorld>(formats::load_robot(robot), formats::load_object(object),
                                                              formats::load_environment(environment), finger_opening,
                                                              joint_values);
  return w;
}

int World::dof() const { return impl_->world->kin().dof(); }
const std::vector<std::string>& World::joint_names() const { return impl_->world->kin().joint_names(); }
Eigen::VectorXd World::lower_limits() const { return impl_->world->kin().lower(); }
Eigen::VectorXd World::upper_limits() const { return impl_->world->kin().upper(); }
Eigen::Isometry3d World::tcp_pose(const Eigen::VectorXd& q) const {
  const auto& kin = impl_->world->kin();
  if (q.size() != kin.dof() || !q.allFinite())
    throw Error("tcp_pose", "q", "needs " + std::to_string(kin.dof()) + " finite joint values");
  std::vector<Eigen::Isometry3d> poses;
  kin.link_poses(q, poses);
  return poses[std::size_t(kin.tip_link())];
}
const runtime::PlacementWorld& World::placement_world() const { return *impl_->world; }
const runtime::Kinematics& World::kinematics() const { return impl_->world->kin(); }

runtime::PlacementResult place(const World& world, const runtime::PlacementQuery& query, const StopCondition& stop,
                               const SolutionCallback& on_solution) {
  runtime::PlacementPlanner planner(world.placement_world(), query);
  return planner.run(stop, on_solution);
}

runtime::ReachableGrasps reachable_grasps(const World& world, const Eigen::Isometry3d& g0, double opening) {
  if (!g0.matrix().allFinite()) throw Error("reachable_grasps", "g0", "not finite");
  return runtime::reachable_grasps(world.placement_world().grasp_graph(), g0, opening);
}

MotionResult plan_motion(const World& world, const Eigen::VectorXd& start, const Eigen::VectorXd& goal,
                         const std::optional<Eigen::Isometry3d>& grasp, double time_limit, std::uint64_t seed,
                         double resolution) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto& pw = world.placement_world();
  const auto& kin = pw.kin();
  for (const auto* q : {&start, &goal}) {
    const char* which = q == &start ? "start" : "goal";
    if (q->size() != kin.dof() || !q->allFinite()) throw Error("plan_motion", which, "needs " + std::to_string(kin.dof()) + " finite joint values");
    if (!kin.within_limits(*q, 1e-9)) throw Error("plan_motion", which, "outside the joint limits");
  }
  if (!(resolution >= 1e-4 && resolution <= 1)) throw Error("plan_motion", "resolution", "must be in [1e-4, 1] rad");
  if (!(time_limit >= 0 && time_limit <= 1e6)) throw Error("plan_motion", "time_limit", "must be in [0, 1e6] s");
  const runtime::TwoLayerChecker checker = grasp ? pw.grasp_checker(*grasp, -1, nullptr) : pw.arm_checker(nullptr);
  auto si = runtime::make_arm_space(kin, checker, resolution);
  MotionResult out;
  const auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  if (!checker.is_free(start)) {
    out.reason = "the start configuration collides";
    out.seconds = since();
    return out;
  }
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> s(si->getStateSpace());
  for (int i = 0; i < kin.dof(); ++i) s[unsigned(i)] = start[i];
  pdef->addStartState(s);
  runtime::MultiGoalRRTConnect planner(si);
  planner.setProblemDefinition(pdef);
  planner.set_seed(seed);
  planner.set_anytime(false);
  planner.setup();
  if (!planner.add_goal(0, std::vector<double>(goal.data(), goal.data() + goal.size()))) {
    out.reason = "the goal configuration collides";
    out.seconds = since();
    return out;
  }
  planner.solve(ob::timedPlannerTerminationCondition(time_limit));
  auto paths = planner.take_paths();
  out.seconds = since();
  if (paths.empty()) {
    out.reason = "no path found in " + std::to_string(time_limit) + " s";
    return out;
  }
  out.solved = true;
  out.path = std::move(paths.front().path);
  return out;
}

StopCondition stop_after_seconds(double seconds) { return runtime::stop_after_seconds(seconds); }
StopCondition stop_after_iterations(long iterations) { return runtime::stop_after_iterations(iterations); }

}  // namespace dmgplace
