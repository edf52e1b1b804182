#include "dmgplace/tools/experiment/experiment_plots.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/experiment/svg_chart.hpp"
#include "dmgplace/tools/system/file_names.hpp"
#include "dmgplace/tools/system/process.hpp"

namespace dmgplace::tools {
namespace {
std::string color_of(const std::string& variant) {
  if (variant == "full") return "#1f77b4";
  if (variant == "random-grasp") return "#ff7f0e";
  if (variant == "no-regrasp") return "#2ca02c";
  return "#7f7f7f";
}

void write_file(const std::filesystem::path& p, const std::string& text) { formats::write_file_atomically(p, text); }

// SVG to PNG with rsvg-convert. The paths go as arguments, never through a shell (the folder may
// hold any character), and absolute, so none starting with '-' is taken for an option.
void svg_to_png(const std::filesystem::path& rsvg, const std::filesystem::path& svg, const std::filesystem::path& png) {
  ProcessOptions o;
  o.stderr_to = StderrTo::merge;  // its messages go into our error
  const ProcessResult r = run_process(
      {rsvg.string(), "-o", std::filesystem::absolute(png).string(), std::filesystem::absolute(svg).string()}, o);
  if (r.exit_code == 0) return;
  const std::string how =
      r.signal ? "killed by signal " + std::to_string(r.signal) : "exit code " + std::to_string(r.exit_code);
  throw Error(png.string(), "", "rsvg-convert failed (" + how + ")" + (r.output.empty() ? "" : ": " + r.output));
}
}  // namespace

std::vector<Curve> experiment_curves(const std::vector<RunRecord>& runs, int samples) {
  std::map<std::pair<std::string, std::string>, std::vector<const RunRecord*>> groups;
  double t_max = 0;
  for (const auto& r : runs) {
    groups[{r.problem, r.variant}].push_back(&r);
    t_max = std::max(t_max, r.time_limit);
  }
  if (!(t_max > 0)) t_max = 1;
  std::vector<Curve> out;
  for (const auto& [key, members] : groups) {
    Curve c;
    c.problem = key.first;
    c.variant = key.second;
    c.runs = int(members.size());
    for (int k = 0; k <= samples; ++k) {
      const double t = t_max * k / samples;
      double sum = 0, sum2 = 0;
      int n = 0;
      for (const RunRecord* r : members) {
        const double v = r->best_at(t);
        if (std::isnan(v)) continue;
        sum += v, sum2 += v * v, ++n;
      }
      const double mean = n ? sum / n : std::nan("");
      const double var = n > 1 ? std::max(0.0, (sum2 - n * mean * mean) / (n - 1)) : 0.0;
      c.t.push_back(t);
      c.mean.push_back(mean);
      c.stderr_.push_back(n ? std::sqrt(var / n) : std::nan(""));
      c.with_solution.push_back(n);
      c.solved_fraction.push_back(double(n) / double(c.runs));
    }
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<std::filesystem::path> plot_experiment(const std::filesystem::path& dir) {
  const auto runs = read_runs(dir);
  if (runs.empty()) throw Error(dir.string(), "runs/", "no finished runs to plot");
  // A problem's folder name names its charts: checked before anything is written.
  for (const auto& r : runs) check_file_name_component(r.problem, (dir / "runs").string(), "problem folder");
  const auto curves = experiment_curves(runs);
  const auto plots = dir / "plots";
  std::filesystem::create_directories(plots);
  std::vector<std::filesystem::path> written;
  std::ostringstream csv;
  csv << "problem,variant,time,mean_objective,stderr,runs_with_solution,runs,solved_fraction\n";
  std::map<std::string, std::vector<const Curve*>> by_problem;
  for (const auto& c : curves) {
    by_problem[c.problem].push_back(&c);
    for (std::size_t i = 0; i < c.t.size(); ++i)
      csv << c.problem << ',' << c.variant << ',' << c.t[i] << ','
          << (std::isnan(c.mean[i]) ? "" : std::to_string(c.mean[i])) << ','
          << (std::isnan(c.stderr_[i]) ? "" : std::to_string(c.stderr_[i])) << ',' << c.with_solution[i] << ','
          << c.runs << ',' << c.solved_fraction[i] << '\n';
  }
  write_file(plots / "curves.csv", csv.str());
  written.push_back(plots / "curves.csv");
  const auto rsvg = find_executable("rsvg-convert");  // no PNG without it
  for (const auto& [problem, cs] : by_problem) {
    std::vector<ChartSeries> objective, solved;
    for (const Curve* c : cs) {
      ChartSeries o{
          c->variant + " (" + std::to_string(c->runs) + " runs)", color_of(c->variant), c->t, c->mean, {}, {}};
      for (std::size_t i = 0; i < c->t.size(); ++i) {
        o.lo.push_back(c->mean[i] - c->stderr_[i]);
        o.hi.push_back(c->mean[i] + c->stderr_[i]);
      }
      objective.push_back(std::move(o));
      solved.push_back({c->variant, color_of(c->variant), c->t, c->solved_fraction, {}, {}});
    }
    ChartOptions oo{problem + ": objective of the best solution found", "time (s)",
                    "mean objective (+- standard error)"};
    ChartOptions so{problem + ": runs with a solution", "time (s)", "fraction of runs"};
    so.y_from_zero = true;
    so.y_max = 1.0;
    for (auto [name, svg] : {std::pair{problem + "_objective", line_chart_svg(objective, oo)},
                             std::pair{problem + "_solved", line_chart_svg(solved, so)}}) {
      const auto svg_path = plots / (name + ".svg");
      write_file(svg_path, svg);
      written.push_back(svg_path);
      if (rsvg) {
        const auto png_path = plots / (name + ".png");
        svg_to_png(*rsvg, svg_path, png_path);
        written.push_back(png_path);
      }
    }
  }
  return written;
}

}  // namespace dmgplace::tools
