#pragma once
// SPEC.yaml for `dmgplace experiment`: a grid of placement problems (each a query file) x variants
// x seeds, one time limit per run. Layout (paths relative to the spec file):
//
//   name: paper_experiment_1
//   artifacts: ../../out/demo/artifacts   # where the queries' artifacts are (or --artifacts)
//   time_limit: 60                        # seconds per run (the paper's)
//   runs: 50                              # seeds 1 .. runs
//   quick: {time_limit: 2, runs: 3}       # the --quick preset (CI)
//   report_times: [1, 5, 20]              # objective reported at these times in summary.csv
//   problems:
//     - {name: cabinet_bottle_side, query: ../queries/cabinet_bottle_side.yaml,
//        variants: [full, random-grasp, no-regrasp]}
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dmgplace/runtime/placement/placement_query.hpp"

namespace dmgplace::tools {

struct ExperimentProblem {
  std::string name;
  std::filesystem::path query;
  std::vector<runtime::PlacementVariant> variants;
};

struct ExperimentSpec {
  std::filesystem::path path;
  std::string name;
  std::filesystem::path artifacts;  // empty: each query's own folder
  double time_limit = 60;
  int runs = 50;
  // Motion planner threads per run (the query option `threads`); unset: each query's own value.
  std::optional<int> threads;
  double quick_time_limit = 2;
  int quick_runs = 3;
  std::vector<double> report_times{1, 5, 20};
  std::vector<ExperimentProblem> problems;
};

ExperimentSpec read_experiment_spec(const std::filesystem::path& path);

}  // namespace dmgplace::tools
