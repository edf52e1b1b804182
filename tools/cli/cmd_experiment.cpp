#include <unistd.h>

#include <iostream>

#include "cli_log.hpp"
#include "commands.hpp"
#include "dmgplace/tools/experiment/experiment_plots.hpp"
#include "dmgplace/tools/experiment/experiment_runner.hpp"

namespace dmgplace::cli {

int run_experiment(const ExperimentArgs& a) {
  const auto spec = tools::read_experiment_spec(a.spec);
  tools::ExperimentOptions o;
  o.out = a.out;
  o.artifacts = a.artifacts;
  o.runs = a.runs;
  o.jobs = a.jobs;
  o.quick = a.quick;
  if (a.time_limit) o.time_limit = *a.time_limit;
  o.redraw_progress = isatty(2);
  const auto t = tools::run_experiment(spec, o, progress_stream());
  std::cout << spec.name << ": " << t.planned << " runs (" << t.ran << " run now, " << t.skipped << " done before), "
            << t.solved << " with a solution; summary in " << (std::filesystem::path(a.out) / "summary.csv").string()
            << "\n";
  return 0;
}

int run_plot(const PlotArgs& a) {
  for (const auto& f : tools::plot_experiment(a.dir)) std::cout << "wrote " << f.string() << "\n";
  return 0;
}

}  // namespace dmgplace::cli
