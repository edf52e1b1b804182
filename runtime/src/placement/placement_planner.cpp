#include "dmgplace/runtime/placement/placement_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <thread>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/triangle_distance.hpp"
#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/runtime/motion/multi_grasp_planner.hpp"
#include "dmgplace/runtime/placement/goal_validator.hpp"
#include "dmgplace/runtime/placement/local_optimizer.hpp"
#include "dmgplace/runtime/placement/retreat.hpp"

namespace dmgplace::runtime {
namespace {
// Unsigned distance from p to the mesh surface (brute force: once per query).
double surface_distance(const TriMesh& m, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)).transpose(), b = m.vertices.row(m.triangles(t, 1)).transpose(),
                          c = m.vertices.row(m.triangles(t, 2)).transpose();
    best = std::min(best, (closest_point_on_triangle(p, a, b, c) - p).norm());
  }
  return best;
}
}  // namespace
namespace {
using Clock = std::chrono::steady_clock;
constexpr int kAnyActions = std::numeric_limits<int>::max();
}  // namespace

PlacementPlanner::Stop stop_after_seconds(double seconds) {
  // Clamped before the cast: 1e12 s in nanoseconds overflows, wrapping the deadline into the past.
  constexpr double kYear = 365.0 * 24 * 3600;
  const double s = std::isnan(seconds) ? 0.0 : std::clamp(seconds, 0.0, kYear);
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  return [end] { return Clock::now() >= end; };
}

PlacementPlanner::Stop stop_after_iterations(long iterations) {
  auto left = std::make_shared<long>(iterations);
  return [left] { return (*left)-- <= 0; };
}

PlacementPlanner::PlacementPlanner(const PlacementWorld& world, PlacementQuery query) : world_(&world), query_(std::move(query)) {
  const Kinematics& kin = world.kin();
  if (query_.q0.size() != kin.dof())
    throw Error(query_.source, "q0", "has " + std::to_string(query_.q0.size()) + " values, the arm has " + std::to_string(kin.dof()) + " joints");
  if (!query_.q0.allFinite()) throw Error(query_.source, "q0", "not finite (NaN or infinity)");
  if (!kin.within_limits(query_.q0, 1e-6)) throw Error(query_.source, "q0", "outside the joint limits");
  if (!query_.g0.matrix().allFinite()) throw Error(query_.source, "initial_grasp", "not finite");
  {
    // The TCP sits between the pads, so a held object's surface is within half the opening of it.
    const auto& gripper = world.object().dmg.gripper;
    const double reach = 0.5 * gripper.max_opening + gripper.contact_tolerance + 0.005;
    const double d = surface_distance(world.object().mesh, query_.g0.translation());
    if (!(d <= reach))
      throw Error(query_.source, "initial_grasp",
                  "the TCP is " + std::to_string(d) + " m from the object's surface; a parallel-jaw grasp holds it within " +
                      std::to_string(reach) + " m (half the gripper's maximum opening plus the contact tolerance)");
  }
  if (query_.volume && (query_.volume->isEmpty() || !query_.volume->min().allFinite() || !query_.volume->max().allFinite()))
    throw Error(query_.source, "volume", "empty or not finite (need xmin <= xmax, ...)");
  check_placement_options(query_.options, query_.source);
}

PlacementPlanner::~PlacementPlanner() = default;

struct PlacementPlanner::Run {
  struct Goal {
    int grasp = -1, face = -1, region = -1;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    double objective = 0;
    Eigen::VectorXd q;
  };

  const PlacementWorld& world;
  const PlacementQuery& q;
  const PlacementOptions& o;
  Clock::time_point t0 = Clock::now();
  std::mt19937_64 rng;
  std::unique_ptr<SearchSpace> space;
  std::unique_ptr<Objective> objective;
  ReachableGrasps reach;
  std::unique_ptr<GraspSpaces> spaces;
  std::unique_ptr<GraspSelector> selector;
  std::unique_ptr<PlacementTree> tree;
  std::unique_ptr<GoalValidator> validator;
  std::unique_ptr<MultiGraspPlanner> motion;
  std::map<int, Goal> goals;
  int next_goal = 0;
  bool exhausted = false;
  double last_trace = -1;
  PlacementResult result;
  long planner_calls = 0, paths = 0, retreat_failures = 0, iterations = 0;

  Run(const PlacementWorld& w, const PlacementQuery& query) : world(w), q(query), o(query.options), rng(query.seed) {}

  double elapsed() const { return std::chrono::duration<double>(Clock::now() - t0).count(); }

  bool better(double value, int actions) const {
    if (result.improvements.empty()) return true;
    const auto& best = result.improvements.back();
    if (value > best.objective + o.tie_tolerance) return true;
    return std::abs(value - best.objective) <= o.tie_tolerance && actions < int(best.in_hand.size());
  }

  PlacementCounters counters() const {
    PlacementCounters c;
    c.iterations = iterations;
    if (validator) {
      const auto& v = validator->counters();
      c.samples = v.samples;
      c.stable = v.stable;
      c.object_free = v.object_free;
      c.with_grasp = v.with_grasp;
      c.ik_calls = v.ik_calls;
      c.ik_solutions = v.ik_solutions;
      c.object_checks = v.object_checks;
      c.goals = v.goals;
    }
    if (spaces) {
      c.collision_checks = spaces->counters().fast;
      c.exact_checks = spaces->counters().exact_pairs + spaces->counters().exact_full;
    }
    if (selector) c.hand_checks = selector->hand_checks();
    c.planner_calls = planner_calls;
    c.paths = paths;
    c.retreat_failures = retreat_failures;
    return c;
  }

  void trace(bool force) {
    const double t = elapsed();
    if (!force && t - last_trace < 0.1) return;
    last_trace = t;
    TracePoint p;
    p.time = t;
    p.best = result.improvements.empty() ? std::nan("") : result.improvements.back().objective;
    p.counters = counters();
    result.trace.push_back(p);
  }

  // Pre-processing; returns the reason when the query cannot have a solution.
  std::string prepare() {
    const Eigen::AlignedBox3d volume = q.volume ? *q.volume : world.env().volume;
    space = std::make_unique<SearchSpace>(world.object(), world.env().regions, volume);
    objective = std::make_unique<Objective>(q.objective, world.env(), world.object(), world.object_spheres().centers);
    if (space->face_count() == 0) return "the object has no stable placement face";
    if (space->region_count() == 0) return "no placement region inside the target volume";
    reach = reachable_grasps(world.grasp_graph(), q.g0, q.g0_opening);
    if (reach.initial_state < 0 || reach.grasps.empty()) return "the object's DMG has no grasp to start from";
    std::vector<ReachableGrasp> grasps = reach.grasps;
    if (q.variant == PlacementVariant::NoRegrasp) grasps.resize(1);
    result.reachable_grasps = int(grasps.size());
    result.initial_state = reach.initial_state;
    spaces = std::make_unique<GraspSpaces>(world, std::move(grasps), q.q0);
    if (!world.exact().is_free(q.q0)) return "the start configuration q0 is in collision: " + world.exact().check(q.q0).contact;
    if (q.variant == PlacementVariant::NoRegrasp && !spaces->usable(0))
      return "holding the object with g0, the start configuration is in collision: " +
             spaces->checker(0)->exact().check(q.q0).contact;
    selector = std::make_unique<GraspSelector>(
        *spaces, q.variant, o.p_accept, o.grasp_tries, [this](int g, const Eigen::Isometry3d& pose) {
          return world.hand_free(pose * spaces->grasp(g).pose);
        });
    tree = std::make_unique<PlacementTree>(*space, o.max_depth, o.ucb_c);
    validator = std::make_unique<GoalValidator>(world, *space, *objective, *spaces, *selector, q);
    auto factory = [this](int g) {
      auto checker = spaces->checker(g);
      return make_arm_space(
          world.kin(), [checker](const Eigen::VectorXd& x) { return checker->is_free(x); }, o.motion_resolution,
          [checker](const Eigen::VectorXd& x, const Eigen::VectorXd& dir, double enough) {
            return checker->free_distance(x, dir, enough);
          });
    };
    motion = std::make_unique<MultiGraspPlanner>(factory, std::vector<double>(q.q0.data(), q.q0.data() + q.q0.size()),
                                                 std::max(1, o.threads), q.seed);
    motion->set_path_validator([this](int g, const JointPath& path) {
      const ExactChecker& exact = spaces->checker(g)->exact();
      return path_valid(path, [&exact](const Eigen::VectorXd& x) { return exact.is_free(x); }, o.motion_resolution);
    });
    return {};
  }

  void add_goal(const GoalCheck& c, const PlacementSample& s) {
    const int id = next_goal++;
    Goal g{c.grasp, s.face, s.region, s.pose, c.objective, c.q};
    if (!motion->add_goal(c.grasp, id, std::vector<double>(c.q.data(), c.q.data() + c.q.size()))) return;
    goals[id] = std::move(g);
  }

  void sample_goals() {
    auto improves = [this](double v) { return better(v, kAnyActions - 1) || better(v, 0); };
    for (int i = 0; i < o.goal_iterations; ++i) {
      const int n = tree->select(rng);
      if (n < 0) {
        exhausted = true;
        return;
      }
      const PlacementSample s = tree->rollout(n, rng);
      const GoalCheck c = validator->check(*tree, s, improves, rng);
      tree->backpropagate(n, c.reward(o));
      if (c.valid()) {
        tree->cache_grasp(n, c.grasp);
        add_goal(c, s);
        return;
      }
    }
  }

  void drop_goals_no_better() {
    for (auto it = goals.begin(); it != goals.end();) {
      if (better(it->second.objective, 0)) {
        ++it;
        continue;
      }
      motion->remove_goal(it->second.grasp, it->first);
      it = goals.erase(it);
    }
  }

  void reached(const GraspPath& gp, const PlacementPlanner::Callback& cb) {
    ++paths;
    auto it = goals.find(gp.found.goal_id);
    if (it == goals.end()) return;  // removed meanwhile: no better than the best any more
    const Goal goal = it->second;
    goals.erase(it);
    const ReachableGrasp& grasp = spaces->grasp(goal.grasp);
    auto checker = spaces->checker(goal.grasp);
    LocalProblem lp;
    lp.kin = &world.kin();
    lp.space = space.get();
    lp.objective = objective.get();
    lp.checker = checker.get();
    lp.tcp_in_object = grasp.pose;
    lp.face = goal.face;
    lp.region = goal.region;
    lp.lift = o.lift;
    const LocalOptimum opt = optimize_locally(lp, goal.q, goal.pose, o);
    std::vector<InHandAction> actions = reach.actions_to(world.grasp_graph(), grasp.state);
    if (!better(opt.objective, int(actions.size()))) return;
    JointPath path = gp.found.path;
    for (const auto& s : opt.steps) path.push_back(std::vector<double>(s.data(), s.data() + s.size()));
    // Every published path is re-validated by the exact layer, local steps included.
    const ExactChecker& exact = checker->exact();
    if (!path_valid(path, [&exact](const Eigen::VectorXd& x) { return exact.is_free(x); }, o.motion_resolution)) return;
    const Eigen::VectorXd q_place = Eigen::Map<const Eigen::VectorXd>(path.back().data(), Eigen::Index(path.back().size()));
    PlacementSolution sol;
    if (o.check_retreat) {
      Eigen::Isometry3d up = opt.pose;
      up.translation().z() += o.lift;
      const Retreat r = plan_retreat(world.kin(), world.released_exact(up), q_place, o.retreat_distance, o.motion_resolution);
      if (!r.ok) {
        ++retreat_failures;
        return;
      }
      sol.retreat = r.path;
    }
    sol.pose = opt.pose;
    sol.objective = opt.objective;
    sol.face = goal.face;
    sol.region = space->source_region(goal.region);
    sol.grasp_state = grasp.state;
    sol.grasp = grasp.pose;
    sol.opening = grasp.opening;
    sol.grasp_cost = grasp.cost;
    sol.in_hand = std::move(actions);
    sol.path = std::move(path);
    sol.time = elapsed();
    sol.counters = counters();
    result.improvements.push_back(std::move(sol));
    if (cb) cb(result.improvements.back());
    trace(true);
    drop_goals_no_better();
  }

  std::string no_solution_reason() const {
    const PlacementCounters c = counters();
    std::ostringstream s;
    s << "no placement found in " << elapsed() << " s";
    if (exhausted) s << " (the search space has no node left)";
    s << ": " << c.samples << " poses sampled, " << c.stable << " stable, " << c.object_free << " of them free of the scene, "
      << c.with_grasp << " with a grasp whose hand fits, " << c.ik_calls << " reached the IK stage (" << c.ik_solutions
      << " solved), " << c.goals << " valid goals, " << c.paths << " arm paths";
    if (c.retreat_failures) s << ", " << c.retreat_failures << " placements without a free retreat";
    return s.str();
  }
};

PlacementResult PlacementPlanner::run(const Stop& stop, const Callback& on_solution) {
  Run r(*world_, query_);
  const std::string impossible = r.prepare();
  if (!impossible.empty()) {
    r.result.reason = impossible;
    r.result.seconds = r.elapsed();
    r.trace(true);
    return std::move(r.result);
  }
  const bool threaded = query_.options.threads > 0;
  if (threaded) r.motion->start();
  r.trace(true);
  while (!stop()) {
    ++r.iterations;
    // Goals leave only when reached or beaten; at capacity the planner catches up first.
    const bool full = int(r.goals.size()) >= query_.options.max_open_goals;
    if (!r.exhausted && !full) r.sample_goals();
    ++r.planner_calls;
    if (!threaded) r.motion->run_round(query_.options.slice_iterations);
    for (const auto& gp : r.motion->take_paths()) r.reached(gp, on_solution);
    if (threaded && (r.exhausted || full)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!threaded && r.exhausted && r.goals.empty()) break;  // nothing left to do, deterministically
    r.trace(false);
  }
  r.motion->stop();
  for (const auto& gp : r.motion->take_paths()) r.reached(gp, on_solution);
  r.result.seconds = r.elapsed();
  r.trace(true);
  r.result.counters = r.counters();
  if (!r.result.solved()) r.result.reason = r.no_solution_reason();
  return std::move(r.result);
}

}  // namespace dmgplace::runtime
