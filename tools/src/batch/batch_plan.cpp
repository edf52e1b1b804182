#include "dmgplace/tools/batch/batch_plan.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <sstream>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/formats/sha256.hpp"
#include "dmgplace/runtime/placement/placement_query.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;
namespace {

// What every identity starts with: a new tool or schema version makes every output new.
nlohmann::json versions() {
  return {{"tool", formats::tool_version()},
          {"object_schema", formats::kObjectSchemaVersion},
          {"environment_schema", formats::kEnvironmentSchemaVersion},
          {"robot_schema", formats::kRobotSchemaVersion}};
}

std::string identity(const nlohmann::json& what) {
  const std::string text = what.dump();
  return formats::sha256_hex(text.data(), text.size());
}

const char* command_of(const std::string& kind) {
  return kind == "robot" ? "bake-robot" : kind == "object" ? "bake-object" : "bake-env";
}

std::string numbers_yaml(const double* v, std::size_t n) {
  std::string s = "[";
  for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + runtime::number_text(v[i]);
  return s + "]";
}

}  // namespace

BatchPlan plan_batch(const BatchManifest& m, const fs::path& out) {
  BatchPlan plan;
  plan.name = m.name;
  plan.out = out;
  std::map<std::string, const BatchTask*> bake_of;  // "kind name" -> task
  std::vector<BatchTask> bakes;
  for (const auto& b : m.bakes) {
    nlohmann::json args = nlohmann::json::array();
    std::map<std::string, std::string> hashes;
    for (const auto& in : b.inputs) hashes[in.string()] = "sha256:" + formats::sha256_file(in);
    for (const auto& a : b.args) args.push_back(hashes.count(a) ? hashes[a] : a);  // bytes, not where they are
    BatchTask t;
    t.kind = b.kind;
    t.name = b.kind + " " + b.name;
    t.id = identity({{"versions", versions()}, {"kind", b.kind}, {"args", args}});
    t.output = out / "artifacts" / (b.kind + "s") / (b.name + "-" + t.id.substr(0, 12) + ".h5");
    t.args = {command_of(b.kind)};
    t.args.insert(t.args.end(), b.args.begin(), b.args.end());
    t.args.insert(t.args.end(), {"--out", t.output.string()});
    (b.kind == "robot" ? t.robot : b.kind == "object" ? t.object : t.environment) = b.name;
    bakes.push_back(std::move(t));
  }
  plan.tasks = bakes;
  for (const auto& t : plan.tasks) bake_of[t.name] = &t;
  std::vector<BatchTask> queries;
  for (const auto& q : m.queries)
    for (const auto& run : q.runs) {
      const std::string &object = run.object, &env = run.environment, &grasp = run.grasp, &variant = run.variant;
      const int seed = run.seed;
      const auto& pose =
          std::find_if(q.grasps.begin(), q.grasps.end(), [&](const auto& g) { return g.first == grasp; })->second;
      const BatchTask* r = bake_of.at("robot " + q.robot);
      const BatchTask* o = bake_of.at("object " + object);
      const BatchTask* e = bake_of.at("environment " + env);
      const auto rel = [&](const BatchTask* b) { return b->output.lexically_relative(out / "artifacts").string(); };
      std::ostringstream y;
      y << "# written by dmgplace batch (" << m.name << ")\n"
        << "robot: " << rel(r) << "\nobject: " << rel(o) << "\nenvironment: " << rel(e) << "\n"
        << "start: " << numbers_yaml(q.start.data(), q.start.size()) << "\n"
        << "initial_grasp: {pose: " << numbers_yaml(pose.data(), 7) << "}\n"
        << "time_limit: " << runtime::number_text(q.time_limit) << "\nseed: " << seed << "\nvariant: " << variant
        << "\n";
      if (!q.extra_yaml.empty()) y << q.extra_yaml << "\n";
      BatchTask t;
      t.kind = "query";
      t.robot = q.robot, t.object = object, t.environment = env, t.grasp = grasp, t.variant = variant;
      t.g0 = pose;
      t.seed = seed;
      t.query_yaml = y.str();
      t.deps = {r->id, o->id, e->id};
      t.id = identity({{"versions", versions()},
                       {"kind", "query"},
                       {"deps", t.deps},
                       {"query", t.query_yaml},
                       {"iterations", q.iterations}});
      t.name = "query " + q.name + "/" + object + "@" + env + "/" + grasp + "/" + variant + "/" + std::to_string(seed);
      t.output = out / "runs" /
                 (q.name + "." + object + "." + env + "." + grasp + "." + variant + "." + std::to_string(seed) + "-" +
                  t.id.substr(0, 12));
      t.args = {"place",       (t.output / "query.yaml").string(),
                "--artifacts", (out / "artifacts").string(),
                "--out",       t.output.string(),
                "--threads",   "0"};
      if (q.iterations > 0) t.args.insert(t.args.end(), {"--iterations", std::to_string(q.iterations)});
      queries.push_back(std::move(t));
    }
  plan.tasks.insert(plan.tasks.end(), queries.begin(), queries.end());
  return plan;
}

bool in_shard(const BatchPlan& plan, std::size_t task, int index, int count) {
  // Position within the task's phase: bakes and queries are each spread over every shard.
  std::size_t first_query = 0;
  while (first_query < plan.tasks.size() && plan.tasks[first_query].kind != "query") ++first_query;
  const std::size_t position = task < first_query ? task : task - first_query;
  return int(position % std::size_t(count)) == index - 1;
}

}  // namespace dmgplace::tools
