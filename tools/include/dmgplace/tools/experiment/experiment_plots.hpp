#pragma once
// `dmgplace plot DIR`: per problem, the mean objective of the runs that have a solution against
// time for each variant (standard error shaded), and the fraction of runs with a solution against
// time; SVG always, PNG when rsvg-convert is installed. Also curves.csv with the numbers drawn.
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/tools/experiment/experiment_results.hpp"

namespace dmgplace::tools {

struct Curve {
  std::string problem, variant;
  std::vector<double> t, mean, stderr_, solved_fraction;
  std::vector<int> with_solution;
  int runs = 0;
};

// Curves on `samples` times from 0 to the longest run's time limit.
std::vector<Curve> experiment_curves(const std::vector<RunRecord>& runs, int samples = 200);
// Writes DIR/plots/<problem>_objective.{svg,png}, <problem>_solved.{svg,png} and curves.csv;
// returns the files written.
std::vector<std::filesystem::path> plot_experiment(const std::filesystem::path& dir);

}  // namespace dmgplace::tools
