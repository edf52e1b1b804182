#include "dmgplace/runtime/placement/placement_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <thread>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/grasp/held_grasp.hpp"
#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/runtime/motion/arm_timing.hpp"
#include "dmgplace/runtime/motion/segment_check.hpp"
#include "dmgplace/runtime/motion/multi_grasp_planner.hpp"
#include "dmgplace/runtime/placement/goal_validator.hpp"
#include "dmgplace/runtime/placement/local_optimizer.hpp"
#include "dmgplace/runtime/placement/push_planner.hpp"
#include "dmgplace/runtime/placement/retreat.hpp"
#include "dmgplace/runtime/placement/retreat_motion.hpp"

namespace dmgplace::runtime {
namespace {
using Clock = std::chrono::steady_clock;
constexpr int kAnyActions = std::numeric_limits<int>::max();

// A ball holding every vertex: its box's center and the farthest vertex from it.
std::pair<Eigen::Vector3d, double> bounding_ball(const TriMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) box.extend(Eigen::Vector3d(mesh.vertices.row(i).transpose()));
  const Eigen::Vector3d c = box.isEmpty() ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(box.center());
  double r = 0;
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    r = std::max(r, (Eigen::Vector3d(mesh.vertices.row(i).transpose()) - c).norm());
  return {c, r};
}
}  // namespace

PlacementPlanner::PlacementPlanner(const PlacementWorld& world, PlacementQuery query)
    : world_(&world), query_(std::move(query)) {
  const Kinematics& kin = world.kinematics();
  if (query_.q0.size() != kin.dof())
    throw Error(
        query_.source, "q0",
        "has " + std::to_string(query_.q0.size()) + " values, the arm has " + std::to_string(kin.dof()) + " joints");
  if (!query_.q0.allFinite()) throw Error(query_.source, "q0", "not finite (NaN or infinity)");
  if (!kin.within_limits(query_.q0, 1e-6)) throw Error(query_.source, "q0", "outside the joint limits");
  if (!query_.g0.matrix().allFinite()) throw Error(query_.source, "initial_grasp", "not finite");
  if (query_.g0_opening && !(std::isfinite(*query_.g0_opening) && *query_.g0_opening > 0))
    throw Error(query_.source, "initial_grasp.opening", "must be finite and > 0 (m)");
  {
    // The TCP sits between the pads, so a held object's surface is within half the opening of it.
    const auto& gripper = world.object().dmg.gripper;
    const double reach = 0.5 * gripper.max_opening + gripper.contact_tolerance + 0.005;
    const double d = surface_distance(world.object().mesh, query_.g0.translation());
    if (!(d <= reach))
      throw Error(query_.source, "initial_grasp",
                  "the TCP is " + std::to_string(d) +
                      " m from the object's surface; a parallel-jaw grasp holds it within " + std::to_string(reach) +
                      " m (half the gripper's maximum opening plus the contact tolerance)");
  }
  if (query_.volume &&
      (query_.volume->isEmpty() || !query_.volume->min().allFinite() || !query_.volume->max().allFinite()))
    throw Error(query_.source, "volume", "empty or not finite (need xmin <= xmax, ...)");
  check_placement_options(query_.options, query_.source);
  if (const auto& r = query_.retreat_configuration) {
    const std::string el = "retreat_configuration";
    if (r->size() != kin.dof())
      throw Error(query_.source, el,
                  "has " + std::to_string(r->size()) + " values, the arm has " + std::to_string(kin.dof()) + " joints");
    if (!r->allFinite()) throw Error(query_.source, el, "not finite (NaN or infinity)");
    if (!kin.within_limits(*r, 1e-6)) throw Error(query_.source, el, "outside the joint limits");
    if (!world.exact().is_free(*r)) throw Error(query_.source, el, "in collision: " + world.exact().check(*r).contact);
  }
  if (query_.pusher)
    pusher_ = std::make_unique<PushPlanner>(world, *query_.pusher, query_.q0, query_.options.motion_resolution,
                                            query_.seed, query_.source);
}

PlacementPlanner::~PlacementPlanner() = default;

struct PlacementPlanner::Run {
  struct Goal {
    int grasp = -1, face = -1, region = -1, node = -1;
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
  std::unique_ptr<PerGraspCheckers> per_grasp;
  std::unique_ptr<GraspSelector> selector;
  std::unique_ptr<PlacementTree> tree;
  std::unique_ptr<GoalValidator> validator;
  std::unique_ptr<MultiGraspPlanner> motion;
  std::map<int, Goal> goals;
  int next_goal = 0;
  bool exhausted = false;
  double last_trace = -1;
  PlacementResult result;
  long planner_calls = 0, paths = 0, paths_rejected = 0, retreat_failures = 0, iterations = 0;
  std::map<double, std::unique_ptr<TwoLayerChecker>> retreat_arms;  // the empty-handed arm per release opening
  std::pair<Eigen::Vector3d, double> object_ball = bounding_ball(world.object().mesh);  // object frame
  long retreat_plans = 0;
  MotionTree retreat_tree;  // rooted at the retreat configuration

  PushPlanner* pusher = nullptr;
  std::map<int, bool> pushable;  // per grasp: pushes_possible's answer
  long push_failures = 0, push_plans_before = 0;
  double push_seconds_before = 0;

  Run(const PlacementWorld& w, const PlacementQuery& query, PushPlanner* p)
      : world(w), q(query), o(query.options), rng(query.seed), pusher(p), push_plans_before(p ? p->planned() : 0),
        push_seconds_before(p ? p->seconds() : 0) {}

  TimingOptions timing() const { return {o.velocity_scaling, o.acceleration_scaling}; }

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
      c.improving = v.improving;
      c.cached_grasps = v.cached_grasps;
      c.ik_calls = v.ik_calls;
      c.ik_solutions = v.ik_solutions;
      c.reachable = v.reachable;
      c.object_checks = v.object_checks;
      c.goals = v.goals;
    }
    if (per_grasp) {
      c.collision_checks = per_grasp->counters().fast;
      c.exact_checks = per_grasp->counters().exact_pairs + per_grasp->counters().exact_full;
    }
    if (selector) c.hand_checks = selector->hand_checks();
    c.planner_calls = planner_calls;
    c.paths = paths;
    c.paths_rejected = paths_rejected;
    if (motion) {
      const auto [checked, dropped] = motion->seeded_nodes();
      c.seeded_checked = long(checked);
      c.seeded_dropped = long(dropped);
    }
    c.retreat_failures = retreat_failures;
    c.push_failures = push_failures;
    if (pusher) {
      c.push_plans = pusher->planned() - push_plans_before;
      c.push_seconds = pusher->seconds() - push_seconds_before;
    }
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

  // g0's finger opening: the query's, else the object's width between the fingers at g0, else
  // (the closing line misses the mesh) the opening of the DMG state g0 snaps to.
  double initial_opening() const {
    const double max_opening = world.object().dmg.gripper.max_opening;
    if (q.g0_opening) return std::min(*q.g0_opening, max_opening);
    if (const auto w = grasp_width(world.object().mesh, q.g0)) return std::min(*w, max_opening);
    return world.grasp_graph().opening(reach.initial_state);
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
    // Grasp 0 is g0 exactly as held (its pose and opening), not the DMG state it snaps to; the
    // in-hand sequences to every other grasp start from that state.
    std::vector<ReachableGrasp> grasps = reach.grasps;
    grasps[0].pose = q.g0;
    grasps[0].opening = initial_opening();
    if (q.variant == PlacementVariant::NoRegrasp) grasps.resize(1);
    result.reachable_grasps = int(grasps.size());
    result.initial_state = reach.initial_state;
    result.snap_distance = reach.snap_distance;
    result.initial_opening = grasps[0].opening;
    per_grasp = std::make_unique<PerGraspCheckers>(world, std::move(grasps), q.q0);
    if (pusher) result.pusher_joints = pusher->kinematics().joint_names();
    if (!world.exact().is_free(q.q0))
      return "the start configuration q0 is in collision: " + world.exact().check(q.q0).contact;
    if (q.variant == PlacementVariant::NoRegrasp && !per_grasp->usable(0))
      return "holding the object with g0, the start configuration is in collision: " +
             world.grasp_exact(q.g0, per_grasp->grasp(0).opening).check(q.q0).contact;
    tree = std::make_unique<PlacementTree>(*space, o.max_depth, o.ucb_c);
    const auto hand_free = [this](int g, const Eigen::Isometry3d& pose) {
      return world.hand_free(pose * per_grasp->grasp(g).pose, per_grasp->grasp(g).opening);
    };
    selector = std::make_unique<GraspSelector>(*per_grasp, *tree, q.variant, o.p_accept, o.hand_tries, hand_free);
    validator = std::make_unique<GoalValidator>(world, *space, *objective, *per_grasp, *selector, q);
    // Each grasp's checker is kept by per_grasp for the whole run, so its space may refer to it.
    auto factory = [this](int g) {
      return make_arm_space(world.kinematics(), *per_grasp->checker(g), o.motion_resolution);
    };
    motion = std::make_unique<MultiGraspPlanner>(factory, std::vector<double>(q.q0.data(), q.q0.data() + q.q0.size()),
                                                 std::max(1, o.threads), q.seed);
    motion->set_share_start_trees(o.share_start_trees);
    motion->set_path_validator([this](int g, const JointPath& path) {
      const ExactChecker& exact = per_grasp->checker(g)->exact();
      return path_valid(
          path, [&exact](const Eigen::VectorXd& x) { return exact.is_free(x); }, o.motion_resolution);
    });
    return {};
  }

  // Whether the pusher (if any) can perform the in-hand actions to grasp g. Asked at the grasp's
  // first valid goal, so grasps that never reach one cost no push planning; a grasp it cannot
  // serve leaves the search.
  bool pushes_possible(int g) {
    if (!pusher) return true;
    if (const auto it = pushable.find(g); it != pushable.end()) return it->second;
    const auto actions = reach.actions_to(world.grasp_graph(), per_grasp->grasp(g).state);
    const bool ok = actions.empty() || pusher->plan(actions, timing()).has_value();
    pushable[g] = ok;
    if (!ok) {
      ++push_failures;
      per_grasp->exclude(g);
    }
    return ok;
  }

  void add_goal(const GoalCheck& c, const PlacementSample& s) {
    if (!pushes_possible(c.grasp)) return;
    const int id = next_goal++;
    Goal g{c.grasp, s.face, s.region, s.node, s.pose, c.objective, c.q};
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
      const GoalCheck c = validator->check(s, improves, rng);
      const bool solved = !result.improvements.empty();
      tree->backpropagate(n, c.reward(o, solved));
      if (solved && c.object_free) selector->record(n, c.grasp, c.kinematically_reachable());
      if (c.kinematically_reachable()) selector->cache(n, c.grasp);
      if (c.valid()) {
        add_goal(c, s);
        return;  // to the planner at once: the first solution comes sooner (the paper runs on to i_max)
      }
    }
  }

  // Goals whose arm path the exact re-check refused: their trees are gone, so they leave.
  void drop_rejected_goals() {
    for (const auto& [grasp, id] : motion->take_rejected()) {
      ++paths_rejected;
      goals.erase(id);
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
    const ReachableGrasp& grasp = per_grasp->grasp(goal.grasp);
    auto checker = per_grasp->checker(goal.grasp);
    LocalProblem lp;
    lp.kin = &world.kinematics();
    lp.space = space.get();
    lp.objective = objective.get();
    lp.checker = checker.get();
    lp.tcp_in_object = grasp.pose;
    lp.face = goal.face;
    lp.region = goal.region;
    lp.lift = o.lift;
    const LocalOptimum opt = optimize_locally(lp, goal.q, goal.pose, o);
    std::vector<InHandAction> actions = reach.actions_to(world.grasp_graph(), grasp.state);
    // The approach passed the exact re-check (the planner's path validator); the local steps
    // must too, each segment at the same states: keep the longest exact-valid prefix.
    const ExactChecker& exact = checker->exact();
    const ValidityFn exact_free = [&exact](const Eigen::VectorXd& x) { return exact.is_free(x); };
    const auto vec = [](const std::vector<double>& v) {
      return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
    };
    std::size_t valid_steps = 0;
    for (Eigen::VectorXd prev = vec(gp.found.path.back()); valid_steps < opt.steps.size(); ++valid_steps) {
      const Eigen::VectorXd next = vec(opt.steps[valid_steps]);
      if (!segment_valid(prev, next, o.motion_resolution, exact_free)) break;
      prev = next;
    }
    // From the furthest step back to the goal itself: where the hand cannot withdraw from the
    // optimum, an earlier step (or the goal) may still be a solution.
    for (int k = int(valid_steps); k >= 0; --k) {
      const Eigen::Isometry3d pose = k == 0 ? goal.pose : opt.poses[std::size_t(k - 1)];
      const double value = k == 0 ? opt.start_objective : opt.values[std::size_t(k - 1)];
      if (!better(value, int(actions.size()))) return;
      JointPath path = gp.found.path;
      path.insert(path.end(), opt.steps.begin(), opt.steps.begin() + k);
      PlacementSolution sol;
      if (o.check_retreat && !plan_whole_retreat(pose, path, grasp.opening, sol)) {
        ++retreat_failures;
        continue;
      }
      publish(std::move(sol), goal, pose, value, std::move(path), std::move(actions), cb);
      return;
    }
  }

  // The retreat from the placement at the end of `path` (the object at `pose`, held at
  // `grasp_opening`): release, withdraw until clear, then the motion to the retreat
  // configuration. Fills sol.retreat and sol.release_opening; false when there is none. The
  // fingers open release_clearance each; where no retreat is found so, they try opening only as
  // far as the gripper's contact tolerance (a narrower hand fits where a wider one does not).
  bool plan_whole_retreat(const Eigen::Isometry3d& pose, const JointPath& path, double grasp_opening,
                          PlacementSolution& sol) {
    const auto& gripper = world.object().dmg.gripper;
    const double wide = std::min(gripper.max_opening, grasp_opening + 2 * o.release_clearance);
    const double narrow = std::min(wide, grasp_opening + 2 * gripper.contact_tolerance);
    return retreat_at(pose, path, wide, sol) || (narrow < wide && retreat_at(pose, path, narrow, sol));
  }

  // plan_whole_retreat with the fingers opened to `opening` at release.
  bool retreat_at(const Eigen::Isometry3d& pose, const JointPath& path, double opening, PlacementSolution& sol) {
    const auto vec = [](const std::vector<double>& v) {
      return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
    };
    Eigen::Isometry3d up = pose;
    up.translation().z() += o.lift;
    const ExactChecker released = world.released_exact(up, opening);
    const Eigen::VectorXd q_place = vec(path.back());
    // Back along the approach first; where the arm cannot do that (it folds into itself or the
    // scene), straight up: the fingers are open and leave the object either way.
    const Eigen::Vector3d back = -world.kinematics().tip_pose(q_place).linear().col(2);
    const ExactChecker placed = world.placed_exact(up, opening);
    const ValidityFn clear = [&placed](const Eigen::VectorXd& x) { return placed.is_free(x); };
    Retreat r =
        plan_retreat(world.kinematics(), released, q_place, back, o.retreat_distance, o.motion_resolution, clear);
    if (!r.ok && back.z() < 0.99)
      r = plan_retreat(world.kinematics(), released, q_place, Eigen::Vector3d::UnitZ(), o.retreat_distance,
                       o.motion_resolution, clear);
    if (!r.ok) return false;
    const JointPath motion = retreat_motion(placed, opening, up, vec(r.path.back()), path);
    if (motion.empty()) return false;
    sol.release_opening = opening;
    sol.retreat = std::move(r.path);
    sol.retreat.insert(sol.retreat.end(), motion.begin() + 1, motion.end());
    return true;
  }

  // The arm motion from the withdrawn hand to the retreat configuration, the object placed at
  // `object_pose`: the approach (q0 ... placement) retraced where it is free, else planned.
  // Empty when none was found within the budget.
  JointPath retreat_motion(const ExactChecker& placed, double opening, const Eigen::Isometry3d& object_pose,
                           const Eigen::VectorXd& from, const JointPath& approach) {
    auto& arm = retreat_arms[opening];
    if (!arm) arm = std::make_unique<TwoLayerChecker>(world.arm_checker(nullptr, opening));
    RetreatScene scene;
    scene.kin = &world.kinematics_at(opening);
    scene.arm = arm.get();
    scene.placed = &placed;
    scene.spheres = &world.robot().spheres;
    scene.object_center = object_pose * object_ball.first;
    scene.object_radius = object_ball.second;
    RetreatBudget budget;
    budget.resolution = o.motion_resolution;
    budget.iterations = o.retreat_iterations;
    budget.seconds = o.retreat_time;
    budget.seed = q.seed + std::uint64_t(++retreat_plans);
    const Eigen::VectorXd& target = q.retreat_configuration ? *q.retreat_configuration : q.q0;
    JointPath back = retrace_approach(scene, from, approach, o.motion_resolution);
    if (!back.empty() && target != q.q0) {
      const JointPath rest = plan_retreat_motion(scene, q.q0, target, budget);
      if (rest.empty()) back.clear();
      else back.insert(back.end(), rest.begin() + 1, rest.end());
    }
    if (!back.empty()) return back;
    // Planned out from the retreat configuration, on the tree earlier retreats grew, and reversed.
    back = plan_retreat_motion(scene, target, from, budget, &retreat_tree);
    std::reverse(back.begin(), back.end());
    return back;
  }

  void publish(PlacementSolution sol, const Goal& goal, const Eigen::Isometry3d& pose, double value, JointPath path,
               std::vector<InHandAction> actions, const PlacementPlanner::Callback& cb) {
    const ReachableGrasp& grasp = per_grasp->grasp(goal.grasp);
    selector->cache(goal.node, goal.grasp);  // reached and optimised there: cache it again (authors' code)
    sol.pose = pose;
    sol.objective = value;
    sol.face = goal.face;
    sol.region = space->source_region(goal.region);
    sol.grasp_state = grasp.state;
    sol.grasp = grasp.pose;
    sol.opening = grasp.opening;
    sol.grasp_cost = grasp.cost;
    sol.in_hand = std::move(actions);
    if (pusher && !sol.in_hand.empty())
      sol.pushes = pusher->plan(sol.in_hand, timing()).value();  // planned when the grasp was admitted
    sol.path = std::move(path);
    sol.trajectory = time_arm_path(world.kinematics(), sol.path, timing());
    sol.retreat_trajectory = time_arm_path(world.kinematics(), sol.retreat, timing());
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
    s << ": " << c.samples << " poses sampled, " << c.stable << " stable, " << c.object_free
      << " of them free of the scene, " << c.improving << " of those improving; " << c.ik_calls << " IK calls ("
      << c.ik_solutions << " solved, " << c.reachable << " collision-free), " << c.goals << " valid goals, " << c.paths
      << " arm paths";
    if (c.paths_rejected) s << ", " << c.paths_rejected << " arm paths refused by the exact re-check";
    if (c.retreat_failures) s << ", " << c.retreat_failures << " placements without a free retreat";
    if (c.push_failures) s << ", " << c.push_failures << " grasps whose in-hand actions the pusher could not perform";
    return s.str();
  }
};

PlacementResult PlacementPlanner::run(const StopCondition& stop, const Callback& on_solution) {
  Run r(*world_, query_, pusher_.get());
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
    r.drop_rejected_goals();
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
