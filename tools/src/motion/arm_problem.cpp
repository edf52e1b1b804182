#include "dmgplace/tools/motion/arm_problem.hpp"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/util/Console.h>

#include <chrono>
#include <optional>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/environment/environment_model.hpp"
#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/tools/environment/distance_field.hpp"
#include "dmgplace/tools/environment/embree_scene.hpp"
#include "dmgplace/tools/environment/environment_geometry.hpp"
#include "dmgplace/tools/io/motion_request_reader.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"

namespace ob = ompl::base;

namespace dmgplace::tools {
namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

Eigen::VectorXd chain_values(const runtime::Kinematics& kin, const std::map<std::string, double>& values,
                             const std::string& file, const std::string& what) {
  Eigen::VectorXd q(kin.dof());
  for (int i = 0; i < kin.dof(); ++i) {
    auto it = values.find(kin.joint_names()[std::size_t(i)]);
    if (it == values.end()) throw Error(file, what, "no value for joint '" + kin.joint_names()[std::size_t(i)] + "'");
    q[i] = it->second;
  }
  return q;
}

double path_length(const runtime::JointPath& path) {
  double len = 0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    double s = 0;
    for (std::size_t k = 0; k < path[i].size(); ++k) s += (path[i][k] - path[i - 1][k]) * (path[i][k] - path[i - 1][k]);
    len += std::sqrt(s);
  }
  return len;
}
}  // namespace

std::shared_ptr<const ArmRobot> load_arm_robot(const std::filesystem::path& robot_h5) {
  auto r = std::make_shared<ArmRobot>();
  r->robot = formats::load_robot(robot_h5);
  const auto& m = r->robot.model;
  r->kin = std::make_unique<runtime::Kinematics>(m, m.arm_base, m.arm_tip);
  r->fast = std::make_unique<runtime::SphereFieldChecker>(*r->kin, r->robot.spheres,
                                                          runtime::PrimitiveObstacles::from_scene(Scene{}));
  r->fast->set_self_tables(r->robot.self_tables);
  r->exact = std::make_unique<runtime::ExactChecker>(*r->kin, Scene{});
  return r;
}

namespace {
// The fast layer over p's distance field: the robot's self tables, and the scene's primitives
// where it has any (null: none).
runtime::SphereFieldChecker field_checker(const ArmProblem& p, double band,
                                          std::shared_ptr<const runtime::PrimitiveObstacles> primitives) {
  runtime::SphereFieldChecker fast(*p.kin, p.robot->robot.spheres, p.sdf, band);
  fast.set_self_tables(p.robot->robot.self_tables);
  if (primitives) fast.set_exact_obstacles(std::move(primitives));
  return fast;
}

// The exact layer in p's scene and the two-layer checker over `fast`; setup timed from t0.
void attach_checkers(ArmProblem& p, runtime::SphereFieldChecker fast, Clock::time_point t0) {
  p.exact = std::make_unique<runtime::ExactChecker>(p.robot->exact->with_kinematics(*p.kin).with_scene(p.scene));
  p.checker = std::make_unique<runtime::TwoLayerChecker>(std::move(fast), *p.exact);
  p.setup_seconds = since(t0);
}
}  // namespace

ArmProblem load_arm_problem(const std::filesystem::path& robot_h5, const std::filesystem::path& scene_yaml,
                            const std::filesystem::path& request_yaml, const ArmProblemOptions& o) {
  return load_arm_problem(load_arm_robot(robot_h5), scene_yaml, request_yaml, o);
}

ArmProblem load_arm_problem(std::shared_ptr<const ArmRobot> robot, const std::filesystem::path& scene_yaml,
                            const std::filesystem::path& request_yaml, const ArmProblemOptions& o) {
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);  // OMPL's per-solve chatter is not ours to print
  ArmProblem p;
  p.robot = std::move(robot);
  const auto& model = p.robot->robot.model;
  p.scene = load_scene(scene_yaml);
  const MotionRequest req = read_motion_request(request_yaml);
  p.kin = std::make_unique<runtime::Kinematics>(*p.robot->kin);
  for (const auto& [name, value] : req.start) {
    const int j = model.joint_index(name);
    if (j < 0) throw Error(request_yaml.string(), "start_state", "robot has no joint '" + name + "'");
    const bool in_chain =
        std::find(p.kin->joint_names().begin(), p.kin->joint_names().end(), name) != p.kin->joint_names().end();
    if (!in_chain && model.joints[std::size_t(j)].mimic < 0 && model.joints[std::size_t(j)].type != JointType::Fixed)
      p.kin->set_joint_value(name, value);
  }
  p.start = chain_values(*p.kin, req.start, request_yaml.string(), "start_state");
  p.goal = chain_values(*p.kin, req.goal, request_yaml.string(), "goal_constraints");
  // The scene's part: a few primitives serve the fast layer as they are; else a distance field.
  const auto t0 = Clock::now();
  const auto primitives = o.exact_primitives ? runtime::PrimitiveObstacles::from_scene(p.scene) : nullptr;
  std::optional<runtime::SphereFieldChecker> fast;
  if (primitives && primitives->all_have_bits() && !o.always_field) {
    fast.emplace(p.robot->fast->with_kinematics(*p.kin));
    fast->set_exact_obstacles(primitives);
  } else {
    const EnvironmentGeometry geometry = make_environment_geometry(p.scene);
    const EmbreeScene embree(geometry);
    const Eigen::AlignedBox3d box(Eigen::Vector3d(-o.reach, -o.reach, -0.3),
                                  Eigen::Vector3d(o.reach, o.reach, o.reach + 0.5));
    p.sdf = std::make_shared<runtime::Grid3>(
        runtime::to_grid(distance_field(embree, grid_covering(box, o.sdf_resolution), o.sdf_band, 1)));
    p.bake_seconds = since(t0);
    fast.emplace(field_checker(p, o.sdf_band, primitives));
  }
  attach_checkers(p, std::move(*fast), t0);
  return p;
}

ArmProblem arm_problem_in_environment(std::shared_ptr<const ArmRobot> robot, const formats::EnvironmentArtifact& env) {
  if (env.sdf.empty()) throw Error("environment", "sdf", "not baked: the fast layer needs the distance field");
  ArmProblem p;
  p.robot = std::move(robot);
  p.scene = env.scene;
  p.kin = std::make_unique<runtime::Kinematics>(*p.robot->kin);
  const auto t0 = Clock::now();
  p.sdf = std::make_shared<runtime::Grid3>(runtime::to_grid(env.sdf));
  attach_checkers(p, field_checker(p, env.sdf.band, runtime::PrimitiveObstacles::from_scene(p.scene)), t0);
  return p;
}

PlanOutcome plan_ours(const ArmProblem& p, double time_limit, double resolution, std::uint64_t seed) {
  PlanOutcome out;
  const auto t0 = Clock::now();
  auto si = runtime::make_arm_space(*p.kin, *p.checker, resolution);
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start(si->getStateSpace());
  for (int i = 0; i < p.kin->dof(); ++i) start[unsigned(i)] = p.start[i];
  pdef->addStartState(start);
  runtime::MultiGoalRRTConnect planner(si);
  planner.setProblemDefinition(pdef);
  planner.set_seed(seed);
  planner.set_anytime(false);
  planner.setup();
  std::vector<double> goal(p.goal.data(), p.goal.data() + p.goal.size());
  if (!planner.add_goal(0, goal)) {
    out.seconds = out.first_path_seconds = since(t0);
    return out;
  }
  const double setup = out.planner_setup_seconds = since(t0);
  planner.solve(ob::timedPlannerTerminationCondition(time_limit));
  out.seconds = since(t0);
  out.first_path_seconds = out.seconds;
  auto paths = planner.take_paths();
  if (paths.empty()) return out;
  out.first_path_seconds = setup + paths[0].time_connected;
  out.path = paths[0].path;
  judge_path(p, out, resolution);
  return out;
}

void judge_path(const ArmProblem& p, PlanOutcome& out, double resolution) {
  out.solved = true;
  out.length = path_length(out.path);
  out.valid = runtime::path_valid(
      out.path, [&](const Eigen::VectorXd& q) { return p.exact->is_free(q); }, resolution);
}

}  // namespace dmgplace::tools
