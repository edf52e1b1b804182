#include "batch_dataset.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {
using nlohmann::ordered_json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::array<const char*, 7> kPoseNames{"x", "y", "z", "qx", "qy", "qz", "qw"};
constexpr std::array<const char*, 3> kAxisNames{"x", "y", "z"};

// Typed access to result.json by JSON pointer; errors name the file and the field.
class ResultJson {
 public:
  ResultJson(const ordered_json& root, const std::string& file) : root_(root), file_(file) {}

  const ordered_json& at(const std::string& pointer) const {
    const ordered_json::json_pointer p(pointer);
    if (!root_.contains(p)) throw Error(file_, field(pointer), "missing");
    return root_.at(p);
  }
  // A number; null (how NaN is written) reads as NaN.
  double real(const std::string& pointer) const {
    const auto& v = at(pointer);
    if (v.is_null()) return kNaN;
    if (!v.is_number()) throw Error(file_, field(pointer), "is not a number");
    return v.get<double>();
  }
  std::int64_t integer(const std::string& pointer) const {
    const auto& v = at(pointer);
    if (!v.is_number_integer()) throw Error(file_, field(pointer), "is not an integer");
    return v.get<std::int64_t>();
  }
  std::string text(const std::string& pointer) const {
    const auto& v = at(pointer);
    if (!v.is_string()) throw Error(file_, field(pointer), "is not a string");
    return v.get<std::string>();
  }
  bool flag(const std::string& pointer) const {
    const auto& v = at(pointer);
    if (!v.is_boolean()) throw Error(file_, field(pointer), "is not true or false");
    return v.get<bool>();
  }
  // An array, of `size` elements unless `size` is negative.
  const ordered_json& array(const std::string& pointer, long size = -1) const {
    const auto& v = at(pointer);
    if (!v.is_array()) throw Error(file_, field(pointer), "is not an array");
    if (size >= 0 && v.size() != std::size_t(size))
      throw Error(file_, field(pointer),
                  "has " + std::to_string(v.size()) + " elements, expected " + std::to_string(size));
    return v;
  }
  const std::string& file() const { return file_; }

 private:
  static std::string field(const std::string& pointer) { return pointer.substr(1); }
  const ordered_json& root_;
  const std::string& file_;
};

std::string at_index(const std::string& pointer, std::size_t k) { return pointer + "/" + std::to_string(k); }

// `prefix`_x ... `prefix`_qw from a 7-element pose, or NaN for each.
void add_pose(DatasetTable& t, const std::string& prefix, const ResultJson* r, const std::string& pointer) {
  if (r) r->array(pointer, 7);
  for (std::size_t k = 0; k < kPoseNames.size(); ++k)
    t.add(prefix + "_" + kPoseNames[k], r ? r->real(at_index(pointer, k)) : kNaN);
}

void add_vector(DatasetTable& t, const std::string& prefix, const ResultJson* r, const std::string& pointer) {
  if (r) r->array(pointer, 3);
  for (std::size_t k = 0; k < kAxisNames.size(); ++k)
    t.add(prefix + "_" + kAxisNames[k], r ? r->real(at_index(pointer, k)) : kNaN);
}

std::vector<std::string> counter_keys(const ResultJson& r, const std::string& pointer) {
  const auto& c = r.at(pointer);
  if (!c.is_object()) throw Error(r.file(), pointer.substr(1), "is not an object");
  std::vector<std::string> keys;
  for (const auto& [k, v] : c.items()) keys.push_back(k);
  return keys;
}

// The counters at `pointer`, one column each, named as in result.json (in any order there).
void add_counters(DatasetTable& t, const std::vector<std::string>& names, const ResultJson& r,
                  const std::string& pointer) {
  auto keys = counter_keys(r, pointer), expected = names;
  std::sort(keys.begin(), keys.end()), std::sort(expected.begin(), expected.end());
  if (keys != expected)
    throw Error(r.file(), pointer.substr(1),
                "names other counters than the first run's (runs of mixed dmgplace versions?)");
  for (const auto& n : names) t.add(n, r.integer(pointer + "/" + n));
}

void add_task_columns(DatasetTable& runs, const BatchTask& task, const std::string& file) {
  if (task.deps.size() < 3)
    throw Error(file, "", "its task in batch.json (" + task.name + ") names fewer than three bakes (corrupt plan?)");
  runs.add("task_id", task.id), runs.add("robot", task.robot), runs.add("object", task.object);
  runs.add("environment", task.environment), runs.add("grasp", task.grasp), runs.add("variant", task.variant);
  runs.add("seed", std::int64_t(task.seed));
  runs.add("robot_artifact", task.deps[0]), runs.add("object_artifact", task.deps[1]);
  runs.add("environment_artifact", task.deps[2]);
  for (std::size_t k = 0; k < kPoseNames.size(); ++k) runs.add(std::string("g0_") + kPoseNames[k], task.g0[k]);
}

// The best solution's summary; `r` null for an unsolved run (NaN, -1 and 0 then).
void add_best_columns(DatasetTable& runs, const ResultJson* r) {
  auto real = [&](const char* column, const char* pointer) { runs.add(column, r ? r->real(pointer) : kNaN); };
  auto integer = [&](const char* column, const char* pointer, std::int64_t none) {
    runs.add(column, r ? r->integer(pointer) : none);
  };
  auto count = [&](const char* column, const char* pointer) {
    runs.add(column, r ? std::int64_t(r->array(pointer).size()) : std::int64_t(0));
  };
  real("objective", "/best/objective");
  real("first_solution_time", "/improvements/0/time");
  real("solution_time", "/best/time");
  integer("face", "/best/face", -1);
  integer("region", "/best/region", -1);
  integer("grasp_state", "/best/grasp/state", -1);
  real("opening", "/best/grasp/opening");
  real("grasp_cost", "/best/grasp/cost");
  count("in_hand_actions", "/best/in_hand");
  count("path_waypoints", "/best/path");
  count("retreat_waypoints", "/best/retreat");
  real("release_opening", "/best/release_opening");
  real("duration", "/best/duration");
  real("retreat_duration", "/best/retreat_duration");
  add_pose(runs, "pose", r, "/best/pose");
}

void add_run_columns(DatasetTable& runs, const ResultJson& r, std::size_t dof) {
  const bool solved = r.flag("/solved");
  runs.add("solved", solved);
  runs.add("reason", solved ? std::string() : r.text("/reason"));
  runs.add("seconds", r.real("/seconds"));
  runs.add("improvements", std::int64_t(r.array("/improvements").size()));
  runs.add("reachable_grasps", r.integer("/reachable_grasps"));
  runs.add("initial_state", r.integer("/initial_state"));
  runs.add("snap_distance", r.real("/snap_distance"));
  runs.add("initial_opening", r.real("/initial_opening"));
  runs.add("dof", std::int64_t(dof));
  add_best_columns(runs, solved ? &r : nullptr);
}

// One row per waypoint of the array at `pointer`: run, step, then q0 ... (one per joint).
void add_waypoints(DatasetTable& t, std::int64_t run, const ResultJson& r, const std::string& pointer,
                   std::size_t dof) {
  const auto& waypoints = r.array(pointer);
  for (std::size_t k = 0; k < waypoints.size(); ++k) {
    const std::string w = at_index(pointer, k);
    r.array(w, long(dof));
    t.add("run", run), t.add("step", std::int64_t(k));
    for (std::size_t j = 0; j < dof; ++j) t.add("q" + std::to_string(j), r.real(at_index(w, j)));
    t.end_row();
  }
}

void add_finger_points(DatasetTable& fingers, std::int64_t run, std::int64_t action, std::int64_t finger,
                       const ResultJson& r, const std::string& pointer) {
  const auto& points = r.array(pointer);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::string p = at_index(pointer, k);
    r.array(p, 3);
    fingers.add("run", run), fingers.add("action", action), fingers.add("finger", finger);
    fingers.add("step", std::int64_t(k));
    for (std::size_t i = 0; i < kAxisNames.size(); ++i) fingers.add(kAxisNames[i], r.real(at_index(p, i)));
    fingers.end_row();
  }
}

// One row per in-hand action of the best solution; fields a type lacks are NaN.
void add_actions(DatasetTables& t, std::int64_t run, const ResultJson& r) {
  const auto& actions = r.array("/best/in_hand");
  for (std::size_t k = 0; k < actions.size(); ++k) {
    const std::string a = at_index("/best/in_hand", k);
    const std::string type = r.text(a + "/type");
    if (type != "push" && type != "rotate")
      throw Error(r.file(), a.substr(1) + "/type", "is '" + type + "', expected push or rotate");
    const bool push = type == "push";
    const ResultJson* pushed = push ? &r : nullptr;
    const ResultJson* rotated = push ? nullptr : &r;
    const auto row = std::int64_t(t.actions.rows());
    t.actions.add("run", run), t.actions.add("step", std::int64_t(k)), t.actions.add("type", type);
    t.actions.add("from_state", r.integer(a + "/from_state")), t.actions.add("to_state", r.integer(a + "/to_state"));
    t.actions.add("distance", push ? r.real(a + "/distance") : kNaN);
    add_vector(t.actions, "push_direction", pushed, a + "/push_direction");
    t.actions.add("angle", push ? kNaN : r.real(a + "/angle"));
    add_vector(t.actions, "axis", rotated, a + "/axis");
    add_vector(t.actions, "pivot", rotated, a + "/pivot");
    t.actions.end_row();
    add_finger_points(t.fingers, run, row, 1, r, a + "/finger1_path");
    add_finger_points(t.fingers, run, row, 2, r, a + "/finger2_path");
  }
}

// One row per improvement (the objective trace), with the counters when it was found.
void add_trace(DatasetTable& trace, std::int64_t run, const ResultJson& r, const std::vector<std::string>& counters) {
  const auto& improvements = r.array("/improvements");
  for (std::size_t k = 0; k < improvements.size(); ++k) {
    const std::string s = at_index("/improvements", k);
    trace.add("run", run), trace.add("step", std::int64_t(k));
    trace.add("time", r.real(s + "/time")), trace.add("objective", r.real(s + "/objective"));
    trace.add("face", r.integer(s + "/face")), trace.add("region", r.integer(s + "/region"));
    trace.add("grasp_state", r.integer(s + "/grasp/state"));
    trace.add("in_hand_actions", std::int64_t(r.array(s + "/in_hand").size()));
    add_pose(trace, "pose", &r, s + "/pose");
    add_counters(trace, counters, r, s + "/counters");
    trace.end_row();
  }
}

}  // namespace

std::vector<std::pair<std::string, const DatasetTable*>> DatasetTables::all() const {
  return {{"runs", &runs},       {"path", &path},   {"retreat", &retreat}, {"actions", &actions},
          {"fingers", &fingers}, {"trace", &trace}, {"joints", &joints},   {"offsets", &offsets}};
}

// The per-run tables' fixed columns, so that a table no run adds to still names them.
DatasetBuilder::DatasetBuilder() {
  for (auto* waypoints : {&t_.path, &t_.retreat}) waypoints->declare<std::int64_t>({"run", "step"});
  t_.actions.declare<std::int64_t>({"run", "step"});
  t_.actions.declare<std::string>({"type"});
  t_.actions.declare<std::int64_t>({"from_state", "to_state"});
  t_.actions.declare<double>({"distance", "push_direction_x", "push_direction_y", "push_direction_z", "angle", "axis_x",
                              "axis_y", "axis_z", "pivot_x", "pivot_y", "pivot_z"});
  t_.fingers.declare<std::int64_t>({"run", "action", "finger", "step"});
  t_.fingers.declare<double>({"x", "y", "z"});
  t_.trace.declare<std::int64_t>({"run", "step"});
  t_.trace.declare<double>({"time", "objective"});
  t_.trace.declare<std::int64_t>({"face", "region", "grasp_state", "in_hand_actions"});
  t_.trace.declare<double>({"pose_x", "pose_y", "pose_z", "pose_qx", "pose_qy", "pose_qz", "pose_qw"});
}

void DatasetBuilder::add_offsets_row() {
  for (const auto& [name, table] : t_.all())
    if (table != &t_.joints && table != &t_.offsets && table != &t_.runs)
      t_.offsets.add(name, std::int64_t(table->rows()));
  t_.offsets.end_row();
}

// The robot's joint count from result.json's joint_names, which every run of one robot must share.
std::size_t DatasetBuilder::robot_dof(const std::string& robot, const ordered_json& result, const std::string& file) {
  const ResultJson r(result, file);
  std::vector<std::string> names;
  for (std::size_t k = 0; k < r.array("/joint_names").size(); ++k) names.push_back(r.text(at_index("/joint_names", k)));
  for (const auto& [known, known_names] : joint_names_)
    if (known == robot && known_names != names)
      throw Error(file, "joint_names", "differ from an earlier run's of robot " + robot);
  if (std::none_of(joint_names_.begin(), joint_names_.end(), [&](const auto& e) { return e.first == robot; }))
    joint_names_.emplace_back(robot, names);
  return names.size();
}

void DatasetBuilder::add_run(const BatchTask& task, const ordered_json& result, const std::string& file) {
  const ResultJson r(result, file);
  if (!result.is_object()) throw Error(file, "", "is not a JSON object");
  if (!counters_known_) {
    counters_known_ = true;
    counter_names_ = counter_keys(r, "/counters");
    for (const auto& n : counter_names_) t_.trace.declare<std::int64_t>({n});
  }
  const std::size_t dof = robot_dof(task.robot, result, file);
  const auto run = std::int64_t(t_.runs.rows());
  add_offsets_row();
  add_task_columns(t_.runs, task, file);
  add_run_columns(t_.runs, r, dof);
  add_counters(t_.runs, counter_names_, r, "/counters");
  t_.runs.end_row();
  if (r.flag("/solved")) {
    add_waypoints(t_.path, run, r, "/best/path", dof);
    add_waypoints(t_.retreat, run, r, "/best/retreat", dof);
    add_actions(t_, run, r);
  }
  add_trace(t_.trace, run, r, counter_names_);
}

DatasetTables DatasetBuilder::finish() {
  add_offsets_row();
  for (const auto& [robot, names] : joint_names_)
    for (std::size_t k = 0; k < names.size(); ++k) {
      t_.joints.add("robot", robot), t_.joints.add("index", std::int64_t(k)), t_.joints.add("name", names[k]);
      t_.joints.end_row();
    }
  return std::move(t_);
}

}  // namespace dmgplace::tools
