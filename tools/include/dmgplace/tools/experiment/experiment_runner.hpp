#pragma once
// `dmgplace experiment`: every (problem, variant, seed) of a spec, each a synchronous
// (deterministic) placement run with the time limit, `jobs` runs at a time. Finished runs (their
// result.json exists) are skipped, so an interrupted experiment resumes where it stopped.
#include <filesystem>
#include <iosfwd>

#include "dmgplace/tools/experiment/experiment_spec.hpp"

namespace dmgplace::tools {

struct ExperimentOptions {
  std::filesystem::path out;
  std::filesystem::path artifacts;  // overrides the spec's
  int runs = 0;                     // > 0 overrides the spec's (or the quick preset's)
  int jobs = 1;
  bool quick = false;            // the spec's quick preset: few seeds, seconds each
  double time_limit = -1;        // >= 0 overrides
  bool redraw_progress = false;  // one progress line redrawn in place (a terminal) or a line per run
};

struct ExperimentTotals {
  int planned = 0, skipped = 0, ran = 0, solved = 0;
};

ExperimentTotals run_experiment(const ExperimentSpec& spec, const ExperimentOptions& options, std::ostream& progress);

}  // namespace dmgplace::tools
