#include "dmgplace/tools/experiment/experiment_results.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {

double RunRecord::best_at(double t) const {
  double best = std::nan("");
  for (const auto& [time, value] : improvements)
    if (time <= t) best = value;
  return best;
}

std::filesystem::path run_folder(const std::filesystem::path& dir, const std::string& problem,
                                 const std::string& variant, int seed) {
  return dir / "runs" / problem / variant / ("seed_" + std::to_string(seed));
}

RunRecord read_run(const std::filesystem::path& path, const std::string& problem, const std::string& variant,
                   int seed) {
  RunRecord r;
  r.problem = problem;
  r.variant = variant;
  r.seed = seed;
  std::ifstream f(path);
  if (!f) throw Error(path.string(), "", "cannot read");
  try {
    const auto j = nlohmann::json::parse(f);
    r.solved = j.at("solved").get<bool>();
    r.seconds = j.at("seconds").get<double>();
    r.time_limit = j.at("query").at("time_limit").get<double>();
    for (const auto& s : j.at("improvements"))
      r.improvements.emplace_back(s.at("time").get<double>(), s.at("objective").get<double>());
    if (r.solved) r.in_hand_actions = int(j.at("best").at("in_hand").size());
    r.samples = j.at("counters").at("samples").get<long>();
    r.goals = j.at("counters").at("goals").get<long>();
    if (j.contains("reason")) r.reason = j.at("reason").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(path.string(), "", std::string("not a dmgplace result: ") + e.what());
  }
  return r;
}

std::vector<RunRecord> read_runs(const std::filesystem::path& dir) {
  std::vector<RunRecord> out;
  const auto runs = dir / "runs";
  if (!std::filesystem::is_directory(runs))
    throw Error(dir.string(), "runs/", "no runs in this folder (run `dmgplace experiment` first)");
  for (const auto& p : std::filesystem::directory_iterator(runs)) {
    if (!p.is_directory()) continue;
    for (const auto& v : std::filesystem::directory_iterator(p.path())) {
      if (!v.is_directory()) continue;
      for (const auto& s : std::filesystem::directory_iterator(v.path())) {
        const auto name = s.path().filename().string();
        const auto result = s.path() / "result.json";
        if (name.rfind("seed_", 0) != 0 || !std::filesystem::exists(result)) continue;
        out.push_back(
            read_run(result, p.path().filename().string(), v.path().filename().string(), std::stoi(name.substr(5))));
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const RunRecord& a, const RunRecord& b) {
    return std::tie(a.problem, a.variant, a.seed) < std::tie(b.problem, b.variant, b.seed);
  });
  return out;
}

void write_summary(const std::filesystem::path& csv, const std::vector<RunRecord>& runs,
                   const std::vector<double>& times) {
  std::ostringstream o;
  o << "problem,variant,seed,solved,first_solution_s,best,in_hand_actions,samples,goals";
  for (double t : times) o << ",objective_at_" << t << "s";
  o << '\n';
  auto num = [](double v) { return std::isnan(v) ? std::string() : std::to_string(v); };
  for (const auto& r : runs) {
    o << r.problem << ',' << r.variant << ',' << r.seed << ',' << (r.solved ? 1 : 0) << ','
      << (r.solved ? std::to_string(r.first_time()) : std::string()) << ','
      << (r.solved ? std::to_string(r.improvements.back().second) : std::string()) << ',' << r.in_hand_actions << ','
      << r.samples << ',' << r.goals;
    for (double t : times) o << ',' << (t <= r.time_limit + 1e-9 ? num(r.best_at(t)) : std::string());
    o << '\n';
  }
  formats::write_file_atomically(csv, o.str());
}

}  // namespace dmgplace::tools
