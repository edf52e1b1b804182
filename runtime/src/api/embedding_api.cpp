#include "dmgplace/runtime.hpp"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>

#include <chrono>
#include <cmath>
#include <future>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/runtime/motion/arm_timing.hpp"
#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"
#include "dmgplace/runtime/placement/placement_world.hpp"
#include "dmgplace/runtime/system/available_cpus.hpp"

namespace dmgplace {
namespace ob = ompl::base;

struct World::Impl {
  std::unique_ptr<runtime::PlacementWorld> world;
};

struct WorldAccess {
  static const runtime::PlacementWorld& of(const World& w) { return *w.impl_->world; }
};

namespace {
const runtime::PlacementWorld& planner_world(const World& w) { return WorldAccess::of(w); }

void check_opening(std::optional<double> finger_opening) {
  if (finger_opening && !(std::isfinite(*finger_opening) && *finger_opening >= 0))
    throw Error("World::load", "finger_opening", "must be finite and >= 0 (m)");
}
}  // namespace

World::World() : impl_(std::make_unique<Impl>()) {}
World::~World() = default;

std::shared_ptr<const World> World::load(const std::filesystem::path& robot, const std::filesystem::path& object,
                                         const std::filesystem::path& environment, std::optional<double> finger_opening,
                                         const std::map<std::string, double>& joint_values) {
  check_opening(finger_opening);
  auto held_object = formats::load_object(object);
  // The held object's FCL tree and sphere cover need its mesh alone: a second core builds them
  // while the robot and the environment load (on one core, the world's constructor does).
  const auto policy = runtime::available_cpus() > 1 ? std::launch::async : std::launch::deferred;
  auto held = std::async(policy, [mesh = held_object.mesh] { return runtime::HeldObjectModels::build(mesh); });
  auto robot_artifact = formats::load_robot(robot);
  auto environment_artifact = formats::load_environment(environment);
  std::shared_ptr<World> w(new World());
  w->impl_->world = std::make_unique<runtime::PlacementWorld>(
      std::move(robot_artifact), std::move(held_object), std::move(environment_artifact), finger_opening.value_or(-1),
      joint_values, std::move(held));
  return w;
}

std::shared_ptr<const World> World::from_artifacts(formats::RobotArtifact robot, formats::ObjectArtifact object,
                                                   formats::EnvironmentArtifact environment,
                                                   std::optional<double> finger_opening,
                                                   const std::map<std::string, double>& joint_values) {
  check_opening(finger_opening);
  std::shared_ptr<World> w(new World());
  w->impl_->world = std::make_unique<runtime::PlacementWorld>(
      std::move(robot), std::move(object), std::move(environment), finger_opening.value_or(-1), joint_values);
  return w;
}

int World::dof() const { return impl_->world->kinematics().dof(); }
const std::vector<std::string>& World::joint_names() const { return impl_->world->kinematics().joint_names(); }
Eigen::VectorXd World::lower_limits() const { return impl_->world->kinematics().lower(); }
Eigen::VectorXd World::upper_limits() const { return impl_->world->kinematics().upper(); }
Eigen::Isometry3d World::tcp_pose(const Eigen::VectorXd& q) const {
  const auto& kin = impl_->world->kinematics();
  if (q.size() != kin.dof() || !q.allFinite())
    throw Error("tcp_pose", "q", "needs " + std::to_string(kin.dof()) + " finite joint values");
  std::vector<Eigen::Isometry3d> poses;
  kin.link_poses(q, poses);
  return poses[std::size_t(kin.tip_link())];
}
const std::vector<std::string>& World::fit_warnings() const { return impl_->world->fit().warnings; }
const runtime::Kinematics& World::kinematics() const { return impl_->world->kinematics(); }

runtime::PlacementResult place(const World& world, const runtime::PlacementQuery& query, const StopCondition& stop,
                               const SolutionCallback& on_solution) {
  runtime::PlacementPlanner planner(planner_world(world), query);
  return planner.run(stop, on_solution);
}

runtime::ReachableGrasps reachable_grasps(const World& world, const Eigen::Isometry3d& g0,
                                          std::optional<double> opening) {
  if (!g0.matrix().allFinite()) throw Error("reachable_grasps", "g0", "not finite");
  if (opening && !(std::isfinite(*opening) && *opening > 0))
    throw Error("reachable_grasps", "opening", "must be finite and > 0 (m)");
  return runtime::reachable_grasps(planner_world(world).grasp_graph(), g0, opening);
}

namespace {

void check_motion_query(const runtime::Kinematics& kin, const MotionQuery& q) {
  for (const auto* x : {&q.start, &q.goal}) {
    const char* which = x == &q.start ? "start" : "goal";
    if (x->size() != kin.dof() || !x->allFinite())
      throw Error("plan_motion", which, "needs " + std::to_string(kin.dof()) + " finite joint values");
    if (!kin.within_limits(*x, 1e-9)) throw Error("plan_motion", which, "outside the joint limits");
  }
  if (q.grasp && !q.grasp->matrix().allFinite()) throw Error("plan_motion", "grasp", "not finite");
  if (!(q.resolution >= 1e-4 && q.resolution <= 1))
    throw Error("plan_motion", "resolution", "must be in [1e-4, 1] rad");
  if (!(q.time_limit >= 0 && q.time_limit <= 1e6)) throw Error("plan_motion", "time_limit", "must be in [0, 1e6] s");
  if (!(q.timing.velocity_scaling > 0 && q.timing.velocity_scaling <= 1))
    throw Error("plan_motion", "timing.velocity_scaling", "must be in (0, 1]");
  if (!(q.timing.acceleration_scaling > 0 && q.timing.acceleration_scaling <= 1))
    throw Error("plan_motion", "timing.acceleration_scaling", "must be in (0, 1]");
  if (!(q.timing.max_deviation > 0 && q.timing.max_deviation <= 1))
    throw Error("plan_motion", "timing.max_deviation", "must be in (0, 1] rad");
  if (!(q.timing.sample_period > 0 && q.timing.sample_period <= 1))
    throw Error("plan_motion", "timing.sample_period", "must be in (0, 1] s");
}

}  // namespace

MotionResult plan_motion(const World& world, const MotionQuery& query) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto& pw = planner_world(world);
  const auto& kin = pw.kinematics();
  check_motion_query(kin, query);
  const runtime::TwoLayerChecker checker =
      query.grasp ? pw.grasp_checker(*query.grasp, -1, nullptr) : pw.arm_checker(nullptr);
  auto si = runtime::make_arm_space(kin, checker, query.resolution);
  MotionResult out;
  const auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  if (!checker.is_free(query.start)) {
    out.reason = "the start configuration collides";
    out.seconds = since();
    return out;
  }
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> s(si->getStateSpace());
  for (int i = 0; i < kin.dof(); ++i) s[unsigned(i)] = query.start[i];
  pdef->addStartState(s);
  runtime::MultiGoalRRTConnect planner(si);
  planner.setProblemDefinition(pdef);
  planner.set_seed(query.seed);
  planner.set_anytime(false);
  planner.setup();
  if (!planner.add_goal(0, std::vector<double>(query.goal.data(), query.goal.data() + query.goal.size()))) {
    out.reason = "the goal configuration collides";
    out.seconds = since();
    return out;
  }
  planner.solve(ob::timedPlannerTerminationCondition(query.time_limit));
  auto paths = planner.take_paths();
  if (paths.empty()) {
    out.reason = "no path found in " + std::to_string(query.time_limit) + " s";
    out.seconds = since();
    return out;
  }
  out.solved = true;
  out.path = std::move(paths.front().path);
  out.trajectory = runtime::time_arm_path(kin, out.path, query.timing);
  out.seconds = since();
  return out;
}

}  // namespace dmgplace
