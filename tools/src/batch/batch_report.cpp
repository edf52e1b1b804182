#include "dmgplace/tools/batch/batch_report.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_writer.hpp"
#include "dmgplace/tools/batch/batch_state.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;

BatchStatus batch_status(const fs::path& out) {
  const BatchPlan plan = read_plan(out);
  BatchStatus s;
  double finished_seconds = 0;
  for (const auto& t : plan.tasks) {
    BatchStatus::Entry e{t.id, t.name, t.kind, "pending", "", 0};
    std::error_code ec;
    if (const auto r = read_record(out, t.id)) {
      e.seconds = r->seconds;
      e.error = r->error;
      e.state = r->ok ? "done" : "failed";
      finished_seconds += r->seconds;
    }
    if (e.state == "pending" && fs::exists(out / "state" / (t.id + ".lock"), ec)) e.state = "running";
    (e.state == "done" ? s.done : e.state == "failed" ? s.failed : e.state == "running" ? s.running : s.pending)++;
    s.tasks.push_back(std::move(e));
  }
  const int finished = s.done + s.failed;
  s.eta_seconds = finished ? finished_seconds / finished * (s.pending + s.running) : 0;
  return s;
}

void print_status(const BatchStatus& s, bool json, std::ostream& os) {
  if (json) {
    nlohmann::ordered_json tasks = nlohmann::ordered_json::array();
    for (const auto& e : s.tasks)
      tasks.push_back({{"id", e.id}, {"name", e.name}, {"kind", e.kind}, {"state", e.state}, {"seconds", e.seconds}, {"error", e.error}});
    os << nlohmann::ordered_json{{"done", s.done}, {"failed", s.failed}, {"running", s.running}, {"pending", s.pending},
                                 {"eta_seconds", s.eta_seconds}, {"tasks", tasks}}
              .dump(1)
       << "\n";
    return;
  }
  for (const auto& e : s.tasks)
    if (e.state != "done") os << e.state << "  " << e.name << (e.error.empty() ? "" : ": " + e.error) << "\n";
  os << s.done << " done, " << s.failed << " failed, " << s.running << " running, " << s.pending << " pending of "
     << s.tasks.size() << "; ETA " << std::lround(s.eta_seconds) << " s on one job\n";
}

std::size_t collect_batch(const fs::path& out, const fs::path& dataset) {
  const BatchPlan plan = read_plan(out);
  std::map<std::string, const BatchTask*> by_id;
  for (const auto& t : plan.tasks) by_id[t.id] = &t;
  std::vector<std::string> ids, robots, objects, envs, grasps, variants, robot_ids, object_ids, env_ids;
  std::vector<std::int64_t> seeds, faces, states, actions, waypoints;
  std::vector<std::uint8_t> solved;
  std::vector<double> objective, first, seconds, g0, pose;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& t : plan.tasks) {
    if (t.kind != "query" || !task_done(out, t)) continue;
    std::ifstream in(t.output / "result.json");
    std::stringstream ss;
    ss << in.rdbuf();
    const auto j = nlohmann::json::parse(ss.str(), nullptr, false);
    if (j.is_discarded()) throw Error((t.output / "result.json").string(), "", "not valid JSON");
    const bool ok = j.value("solved", false);
    ids.push_back(t.id), robots.push_back(t.robot), objects.push_back(t.object), envs.push_back(t.environment);
    grasps.push_back(t.grasp), variants.push_back(t.variant), seeds.push_back(t.seed);
    robot_ids.push_back(t.deps.at(0)), object_ids.push_back(t.deps.at(1)), env_ids.push_back(t.deps.at(2));
    solved.push_back(ok);
    seconds.push_back(j.value("seconds", nan));
    g0.insert(g0.end(), t.g0.begin(), t.g0.end());
    if (ok) {
      const auto& b = j.at("best");
      objective.push_back(b.at("objective"));
      first.push_back(j.at("improvements").at(0).at("time"));
      faces.push_back(b.at("face")), states.push_back(b.at("grasp").at("state"));
      actions.push_back(std::int64_t(b.at("in_hand").size())), waypoints.push_back(std::int64_t(b.at("path").size()));
      for (const auto& x : b.at("pose")) pose.push_back(x.get<double>());  // x y z qx qy qz qw
    } else {
      objective.push_back(nan), first.push_back(nan), faces.push_back(-1), states.push_back(-1), actions.push_back(0),
          waypoints.push_back(0);
      for (int k = 0; k < 7; ++k) pose.push_back(nan);
    }
  }
  formats::ArtifactHeader h;
  h.schema = "dmgplace.dataset";
  h.schema_version = 1;
  h.parameters_json = nlohmann::json{{"batch", plan.name}, {"rows", ids.size()}}.dump();
  formats::H5Writer w(dataset, h);
  const std::size_t n = ids.size();
  for (auto [name, col] : {std::pair{"task_id", &ids}, {"robot", &robots}, {"object", &objects}, {"environment", &envs},
                           {"grasp", &grasps}, {"variant", &variants}, {"robot_artifact", &robot_ids},
                           {"object_artifact", &object_ids}, {"environment_artifact", &env_ids}})
    w.write_strings(std::string("runs/") + name, *col);
  for (auto [name, col] : {std::pair{"seed", &seeds}, {"face", &faces}, {"grasp_state", &states}, {"in_hand_actions", &actions},
                           {"path_waypoints", &waypoints}})
    w.write(std::string("runs/") + name, std::span<const std::int64_t>(*col), {n});
  w.write("runs/solved", std::span<const std::uint8_t>(solved), {n});
  for (auto [name, col] : {std::pair{"objective", &objective}, {"first_solution_time", &first}, {"seconds", &seconds}})
    w.write(std::string("runs/") + name, std::span<const double>(*col), {n});
  w.write("runs/g0", std::span<const double>(g0), {n, 7});
  w.write("runs/pose", std::span<const double>(pose), {n, 7});
  w.commit();
  return n;
}

}  // namespace dmgplace::tools
