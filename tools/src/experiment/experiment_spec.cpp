#include "dmgplace/tools/experiment/experiment_spec.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/yaml_file.hpp"
#include "dmgplace/tools/system/file_names.hpp"

namespace dmgplace::tools {

ExperimentSpec read_experiment_spec(const std::filesystem::path& path) {
  const std::string file = path.string();
  const YAML::Node root = load_yaml_file(path);
  if (!root.IsMap()) throw Error(file, "", "expected a map (name, time_limit, runs, problems, ...)");
  ExperimentSpec s;
  s.path = path;
  const auto dir = path.parent_path();
  auto rel = [&](const std::string& p) {
    const std::filesystem::path x = p;
    return x.is_absolute() ? x : dir / x;
  };
  require_known_keys(root, {"name", "artifacts", "time_limit", "runs", "threads", "quick", "report_times", "problems"},
                     file, "");
  try {
    s.name = root["name"] ? root["name"].as<std::string>() : path.stem().string();
    if (root["artifacts"]) s.artifacts = rel(root["artifacts"].as<std::string>());
    if (root["time_limit"]) s.time_limit = root["time_limit"].as<double>();
    if (root["runs"]) s.runs = root["runs"].as<int>();
    if (root["threads"]) {
      s.threads = root["threads"].as<int>();
      if (*s.threads < 0 || *s.threads > 256)
        throw Error(file, "threads", "must be in [0, 256] (0: synchronous and deterministic)");
    }
    if (const YAML::Node q = root["quick"]) {
      if (q["time_limit"]) s.quick_time_limit = q["time_limit"].as<double>();
      if (q["runs"]) s.quick_runs = q["runs"].as<int>();
      require_known_keys(q, {"time_limit", "runs"}, file, "quick");
    }
    if (root["report_times"]) s.report_times = root["report_times"].as<std::vector<double>>();
    for (double t : {s.time_limit, s.quick_time_limit})
      if (!(t >= 0 && t <= 1e6)) throw Error(file, "time_limit", "must be a number of seconds in [0, 1e6]");
    if (s.runs < 1 || s.quick_runs < 1 || s.runs > 100000 || s.quick_runs > 100000)
      throw Error(file, "runs", "must be in [1, 100000]");
    for (double t : s.report_times)
      if (!(t >= 0 && t <= 1e6)) throw Error(file, "report_times", "each must be a number of seconds in [0, 1e6]");
    const YAML::Node problems = root["problems"];
    if (!problems || !problems.IsSequence() || problems.size() == 0) throw Error(file, "problems", "missing or empty");
    std::set<std::string> names;
    for (std::size_t i = 0; i < problems.size(); ++i) {
      const YAML::Node p = problems[i];
      const std::string where = "problems[" + std::to_string(i) + "]";
      if (!p["name"] || !p["query"]) throw Error(file, where, "needs name and query");
      require_known_keys(p, {"name", "query", "variants"}, file, where);
      ExperimentProblem e;
      e.name = p["name"].as<std::string>();
      check_file_name_component(e.name, file, where + ".name");  // it names the runs' folder
      if (!names.insert(e.name).second) throw Error(file, where + ".name", "'" + e.name + "' appears twice");
      e.query = rel(p["query"].as<std::string>());
      const auto variants =
          p["variants"] ? p["variants"].as<std::vector<std::string>>() : std::vector<std::string>{"full"};
      for (const auto& v : variants) {
        const auto parsed = runtime::parse_variant(v);
        if (!parsed)
          throw Error(file, where + ".variants", "unknown variant '" + v + "' (full, random-grasp, no-regrasp)");
        e.variants.push_back(*parsed);
      }
      s.problems.push_back(std::move(e));
    }
  } catch (const YAML::Exception& e) {
    throw Error(file, e.mark.is_null() ? "" : "line " + std::to_string(e.mark.line + 1), "malformed spec: " + e.msg);
  }
  return s;
}

}  // namespace dmgplace::tools
