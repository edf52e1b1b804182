#pragma once
// Reading an experiment folder back: DIR/runs/<problem>/<variant>/seed_<k>/result.json, one per
// run, as written by `dmgplace place` and `dmgplace experiment`.
#include <filesystem>
#include <string>
#include <vector>

namespace dmgplace::tools {

struct RunRecord {
  std::string problem, variant;
  int seed = 0;
  bool solved = false;
  double seconds = 0;
  double time_limit = 0;
  std::vector<std::pair<double, double>> improvements;  // (time, objective), in order
  int in_hand_actions = -1;                             // of the best solution
  long samples = 0, goals = 0;
  std::string reason;
  // Best objective found by time t (NaN before the first solution).
  double best_at(double t) const;
  double first_time() const { return improvements.empty() ? -1 : improvements.front().first; }
};

std::filesystem::path run_folder(const std::filesystem::path& dir, const std::string& problem,
                                 const std::string& variant, int seed);
// One run's result.json (errors name the file).
RunRecord read_run(const std::filesystem::path& result_json, const std::string& problem, const std::string& variant,
                   int seed);
// Every finished run under DIR/runs, sorted by problem, variant, seed.
std::vector<RunRecord> read_runs(const std::filesystem::path& dir);
// summary.csv: one row per run with the objective at each of `report_times`.
void write_summary(const std::filesystem::path& csv, const std::vector<RunRecord>& runs,
                   const std::vector<double>& report_times);

}  // namespace dmgplace::tools
