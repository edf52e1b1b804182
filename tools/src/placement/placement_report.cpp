#include "dmgplace/tools/placement/placement_report.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {
using nlohmann::ordered_json;
using runtime::PlacementCounters;
using runtime::PlacementSolution;

ordered_json pose_json(const Eigen::Isometry3d& p) {
  const Eigen::Quaterniond q(p.linear());
  return {p.translation().x(), p.translation().y(), p.translation().z(), q.x(), q.y(), q.z(), q.w()};
}

ordered_json vec_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

ordered_json counters_json(const PlacementCounters& c) {
  return {{"iterations", c.iterations},
          {"samples", c.samples},
          {"stable", c.stable},
          {"object_free", c.object_free},
          {"improving", c.improving},
          {"cached_grasps", c.cached_grasps},
          {"ik_calls", c.ik_calls},
          {"ik_solutions", c.ik_solutions},
          {"reachable", c.reachable},
          {"collision_checks", c.collision_checks},
          {"exact_checks", c.exact_checks},
          {"object_checks", c.object_checks},
          {"hand_checks", c.hand_checks},
          {"goals", c.goals},
          {"planner_calls", c.planner_calls},
          {"paths", c.paths},
          {"paths_rejected", c.paths_rejected},
          {"seeded_checked", c.seeded_checked},
          {"seeded_dropped", c.seeded_dropped},
          {"retreat_failures", c.retreat_failures},
          {"push_failures", c.push_failures},
          {"push_plans", c.push_plans}};
}

ordered_json solution_json(const PlacementSolution& s) {
  ordered_json j;
  j["time"] = s.time;
  j["objective"] = s.objective;
  j["pose"] = pose_json(s.pose);
  j["face"] = s.face;
  j["region"] = s.region;
  j["grasp"] = {{"state", s.grasp_state}, {"pose", pose_json(s.grasp)}, {"opening", s.opening}, {"cost", s.grasp_cost}};
  ordered_json actions = ordered_json::array();
  for (const auto& a : s.in_hand) {
    ordered_json x;
    x["type"] = a.type == runtime::GraspMove::Translation ? "push" : "rotate";
    x["from_state"] = a.from_state;
    x["to_state"] = a.to_state;
    if (a.type == runtime::GraspMove::Translation) {
      x["distance"] = a.distance;
      x["push_direction"] = vec_json(a.push_direction);
    } else {
      x["angle"] = a.angle;
      x["axis"] = vec_json(a.axis);
      x["pivot"] = vec_json(a.pivot);
    }
    ordered_json f1 = ordered_json::array(), f2 = ordered_json::array();
    for (const auto& p : a.finger1_path) f1.push_back(vec_json(p));
    for (const auto& p : a.finger2_path) f2.push_back(vec_json(p));
    x["finger1_path"] = f1;
    x["finger2_path"] = f2;
    actions.push_back(x);
  }
  j["in_hand"] = actions;
  ordered_json pushes = ordered_json::array();
  for (const auto& p : s.pushes)
    pushes.push_back({{"action", p.action},
                      {"contact", vec_json(p.contact)},
                      {"direction", vec_json(p.direction)},
                      {"object_before", pose_json(p.object_before)},
                      {"object_after", pose_json(p.object_after)},
                      {"grasp_after", pose_json(p.grasp_after)},
                      {"push_begin", p.push_begin},
                      {"push_end", p.push_end},
                      {"duration", p.trajectory.duration()},
                      {"path", p.path},
                      {"trajectory", ordered_json::parse(trajectory_json_text(p.trajectory))}});
  if (!s.pushes.empty()) j["pushes"] = pushes;
  j["path"] = s.path;
  j["retreat"] = s.retreat;
  j["release_opening"] = s.release_opening;
  j["duration"] = s.trajectory.duration();  // timed trajectories: trajectory.json
  j["retreat_duration"] = s.retreat_trajectory.duration();
  j["counters"] = counters_json(s.counters);
  return j;
}

}  // namespace

std::string solution_line(const PlacementSolution& s) {
  std::ostringstream o;
  const Eigen::Vector3d t = s.pose.translation();
  o << std::fixed << std::setprecision(3) << "[" << std::setw(7) << s.time << " s] objective " << std::setprecision(4)
    << s.objective << std::setprecision(3) << "  at (" << t.x() << ", " << t.y() << ", " << t.z() << ")  face "
    << s.face << "  grasp " << s.grasp_state << " (" << s.in_hand.size() << " in-hand actions)  path " << s.path.size()
    << " waypoints";
  return o.str();
}

std::string result_json(const PlacementQueryFile& q, const runtime::PlacementResult& r,
                        const runtime::Kinematics& kin) {
  ordered_json j;
  j["query"] = {{"file", q.path.string()},
                {"robot", q.robot.string()},
                {"object", q.object.string()},
                {"environment", q.environment.string()},
                {"variant", runtime::to_string(q.query.variant)},
                {"seed", q.query.seed},
                {"time_limit", q.time_limit},
                {"threads", q.query.options.threads},
                {"start", std::vector<double>(q.query.q0.data(), q.query.q0.data() + q.query.q0.size())},
                {"initial_grasp", pose_json(q.query.g0)}};
  if (q.query.pusher)
    j["query"]["pusher"] = {{"arm", q.query.pusher->base + ":" + q.query.pusher->tip},
                            {"tcp", pose_json(q.query.pusher->tcp)}};
  if (const auto others = world_joint_values(q, kin.model()); !others.empty()) j["query"]["joint_values"] = others;
  if (q.query.volume)
    j["query"]["volume"] = {q.query.volume->min().x(), q.query.volume->min().y(), q.query.volume->min().z(),
                            q.query.volume->max().x(), q.query.volume->max().y(), q.query.volume->max().z()};
  ordered_json terms = ordered_json::array();
  for (const auto& t : q.query.objective)
    terms.push_back({{"term", runtime::to_string(t.kind)}, {"weight", t.weight}, {"vector", vec_json(t.vector)}});
  j["query"]["objective"] = terms;
  j["joint_names"] = kin.joint_names();
  j["solved"] = r.solved();
  if (!r.solved()) j["reason"] = r.reason;
  j["seconds"] = r.seconds;
  j["reachable_grasps"] = r.reachable_grasps;
  j["initial_state"] = r.initial_state;
  j["snap_distance"] = r.snap_distance;
  j["initial_opening"] = r.initial_opening;
  j["counters"] = counters_json(r.counters);
  if (!r.pusher_joints.empty()) j["push_seconds"] = r.counters.push_seconds;  // counters are counts; this is time
  if (r.solved()) {
    j["best"] = solution_json(r.best());
    const bool planned = !r.best().pushes.empty();
    if (!r.best().in_hand.empty())
      j["in_hand_execution"] = {{"planned", planned},
                                {"note", planned ? runtime::kInHandPlannedNote : runtime::kInHandExecutionNote}};
    if (planned) j["pusher_joint_names"] = r.pusher_joints;
  }
  ordered_json imp = ordered_json::array();
  for (const auto& s : r.improvements) {
    ordered_json x = solution_json(s);
    x.erase("path");
    x.erase("retreat");
    if (x.contains("pushes"))
      for (auto& p : x["pushes"]) p.erase("path"), p.erase("trajectory");
    imp.push_back(x);
  }
  j["improvements"] = imp;
  return j.dump(2) + "\n";
}

void write_placement_result(const std::filesystem::path& dir, const PlacementQueryFile& q,
                            const runtime::PlacementResult& r, const runtime::Kinematics& kin,
                            TrajectoryFormat format) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(dir.string(), "", "cannot create the output folder: " + ec.message());
  std::ostringstream trace;
  trace << "time,best,iterations,samples,ik_calls,ik_solutions,collision_checks,exact_checks,goals,paths\n";
  for (const auto& p : r.trace) {
    const auto& c = p.counters;
    trace << p.time << ',' << (std::isnan(p.best) ? std::string() : std::to_string(p.best)) << ',' << c.iterations
          << ',' << c.samples << ',' << c.ik_calls << ',' << c.ik_solutions << ',' << c.collision_checks << ','
          << c.exact_checks << ',' << c.goals << ',' << c.paths << '\n';
  }
  formats::write_file_atomically(dir / "trace.csv", trace.str());
  std::ostringstream path;
  path << "segment";
  for (const auto& n : kin.joint_names()) path << ',' << n;
  path << '\n';
  if (r.solved()) {
    for (auto [name, pts] : {std::pair{"approach", &r.best().path}, std::pair{"retreat", &r.best().retreat}})
      for (const auto& w : *pts) {
        path << name;
        for (double v : w) path << ',' << std::setprecision(9) << v;
        path << '\n';
      }
  }
  formats::write_file_atomically(dir / "path.csv", path.str());
  const runtime::Trajectory none;
  const runtime::Trajectory& approach = r.solved() ? r.best().trajectory : none;
  const runtime::Trajectory& retreat = r.solved() ? r.best().retreat_trajectory : none;
  // The pusher's trajectories (one per in-hand action) before the grasping arm's: the order they run in.
  std::string pushes;
  const std::vector<runtime::PushPlan> no_pushes;
  const auto& plans = r.solved() ? r.best().pushes : no_pushes;
  for (const auto& p : plans) pushes += (pushes.empty() ? "" : ",\n") + trajectory_json_text(p.trajectory);
  formats::write_file_atomically(
      dir / "trajectory.json",
      "{\"joint_names\": " + nlohmann::json(kin.joint_names()).dump() +
          ",\n\"approach\": " + trajectory_json_text(approach) + ",\n\"retreat\": " + trajectory_json_text(retreat) +
          (plans.empty() ? std::string()
                         : ",\n\"pusher_joint_names\": " + nlohmann::json(r.pusher_joints).dump() + ",\n\"pushes\": [" +
                               pushes + "]") +
          "}\n");
  if (format == TrajectoryFormat::MoveIt) {
    formats::write_file_atomically(dir / "trajectory_approach.yaml",
                                   moveit_trajectory_yaml(approach, kin.joint_names()));
    formats::write_file_atomically(dir / "trajectory_retreat.yaml", moveit_trajectory_yaml(retreat, kin.joint_names()));
    for (std::size_t i = 0; i < plans.size(); ++i)
      formats::write_file_atomically(dir / ("trajectory_push_" + std::to_string(i + 1) + ".yaml"),
                                     moveit_trajectory_yaml(plans[i].trajectory, r.pusher_joints));
  }
  // Last: result.json marks the run complete (a resumed experiment skips runs that have it).
  formats::write_file_atomically(dir / "result.json", result_json(q, r, kin));
}

}  // namespace dmgplace::tools
