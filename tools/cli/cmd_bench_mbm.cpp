#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>

#include "cli_log.hpp"
#include "commands.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/motion/arm_problem.hpp"
#include "stock_planner.hpp"

namespace dmgplace::cli {
namespace fs = std::filesystem;
namespace {
struct Stats {
  int runs = 0, solved = 0, valid = 0;
  std::vector<double> times, first_times, lengths;  // first_times: to the path before shortcutting
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

void add(Stats& s, const tools::PlanOutcome& o) {
  ++s.runs;
  s.solved += o.solved;
  s.valid += o.solved && o.valid;
  s.times.push_back(o.seconds);  // unsolved runs count with their full time
  s.first_times.push_back(o.first_path_seconds);
  if (o.solved) s.lengths.push_back(o.length);
}

void print(const std::string& name, const Stats& s) {
  if (s.runs == 0) return;
  std::cout << std::left << std::setw(36) << name << " solved " << s.solved << "/" << s.runs << " (valid " << s.valid
            << "), median " << quantile(s.times, 0.5) * 1e3 << " ms, p95 " << quantile(s.times, 0.95) * 1e3
            << " ms, median length " << quantile(s.lengths, 0.5) << "; to the first path (before shortcutting): median "
            << quantile(s.first_times, 0.5) * 1e3 << " ms\n";
}

// A folder's requestNNNN.yaml files, sorted, at most `limit` (0: all).
std::vector<fs::path> list_requests(const std::string& dir, int limit) {
  std::vector<fs::path> requests;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind("request", 0) == 0 && e.path().extension() == ".yaml")
      requests.push_back(e.path());
  std::sort(requests.begin(), requests.end());
  if (limit > 0 && int(requests.size()) > limit) requests.resize(std::size_t(limit));
  if (requests.empty()) throw Error(dir, "", "no requestNNNN.yaml files");
  return requests;
}

// Every run's figures, pooled over the sets.
struct Totals {
  Stats ours, stock;
  Stats planning_alone;  // ours without its space and planner setup (as VAMP's timers count)
  // Ours builds per scene its checkers, and a distance field unless the scene is a few primitives
  // (in dmgplace proper, bake-env does that offline): reported apart from planning, then with it.
  std::vector<double> field_seconds, setup_seconds, setup_and_first;
};

// After the per-set lines: the setup apart, planning alone, a new scene to its first path, the ratio.
void print_totals(const Totals& t, const BenchMbmArgs& a, bool run_ours, bool run_stock) {
  print("all ours", t.ours);
  print("all OMPL RRTConnect+FCL " + a.stock_bvh, t.stock);
  std::cout << "ours' scene setup (checkers; a distance field in " << t.field_seconds.size() << " of "
            << t.setup_seconds.size() << " scenes), not in the planning times above: median "
            << quantile(t.setup_seconds, 0.5) * 1e3 << " ms, p95 " << quantile(t.setup_seconds, 0.95) * 1e3 << " ms";
  if (!t.field_seconds.empty())
    std::cout << " (the field alone: median " << quantile(t.field_seconds, 0.5) * 1e3 << " ms at " << a.sdf_resolution
              << " m)";
  std::cout << "\n";
  if (run_ours) {
    print("all ours, planning alone (no space/planner setup)", t.planning_alone);
    std::vector<double> planner_setup;
    for (std::size_t i = 0; i < t.ours.times.size(); ++i)
      planner_setup.push_back(t.ours.times[i] - t.planning_alone.times[i]);
    std::cout << "ours' space and planner setup per run (in the times above, not in planning alone): median "
              << quantile(planner_setup, 0.5) * 1e3 << " ms\n";
    std::cout << "ours from a new scene to its first path (setup + planning): median "
              << quantile(t.setup_and_first, 0.5) * 1e3 << " ms, p95 " << quantile(t.setup_and_first, 0.95) * 1e3
              << " ms\n";
  }
  if (run_ours && run_stock)
    std::cout << "ratio of medians (stock / ours): " << quantile(t.stock.times, 0.5) / quantile(t.ours.times, 0.5)
              << " with our shortcutting, " << quantile(t.stock.first_times, 0.5) / quantile(t.ours.first_times, 0.5)
              << " to the first path (neither shortened)\n";
}
}  // namespace

int run_bench_mbm(const BenchMbmArgs& a) {
  std::ofstream csv;
  if (!a.csv.empty()) {
    csv.open(a.csv);
    if (!csv) throw Error(a.csv, "", "cannot write");
    csv << "set,problem,planner,run,solved,valid,seconds,length,first_path_seconds,setup_seconds,planner_setup_"
           "seconds\n";
  }
  Totals all;
  const bool run_ours = a.planners != "stock", run_stock = a.planners != "ours";
  const auto robot = tools::load_arm_robot(a.robot);  // once: every scene shares its checkers' robot part
  for (const auto& dir : a.dirs) {
    const std::vector<fs::path> requests = list_requests(dir, a.limit);
    Stats ours, stock;
    const std::string set = fs::path(dir).filename().string();
    for (std::size_t i = 0; i < requests.size(); ++i) {
      const std::string id = requests[i].filename().string().substr(7, 4);
      const fs::path scene = fs::path(dir) / ("scene" + id + ".yaml");
      tools::ArmProblemOptions opt;
      opt.sdf_resolution = a.sdf_resolution;
      opt.always_field = a.field == "always";
      auto problem = tools::load_arm_problem(robot, scene, requests[i], opt);
      std::optional<bench::StockFclChecker> stock_checker;
      if (run_stock)
        stock_checker.emplace(*problem.kin, problem.scene,
                              a.stock_bvh == "obb" ? runtime::FclMeshNodes::Obb : runtime::FclMeshNodes::Obbrss);
      if (problem.sdf) all.field_seconds.push_back(problem.bake_seconds);
      all.setup_seconds.push_back(problem.setup_seconds);
      auto record = [&](const char* planner, int r, const tools::PlanOutcome& o, Stats& set_stats, Stats& pooled) {
        add(set_stats, o);
        add(pooled, o);
        if (csv)
          csv << set << "," << id << "," << planner << "," << r << "," << o.solved << "," << o.valid << "," << o.seconds
              << "," << o.length << "," << o.first_path_seconds << ","
              << (planner == std::string("ours") ? problem.setup_seconds : 0.0) << "," << o.planner_setup_seconds
              << "\n";
      };
      for (int r = 0; r < a.runs; ++r) {
        const auto seed = std::uint64_t(r + 1);
        if (run_ours) {
          const auto o = tools::plan_ours(problem, a.time_limit, a.resolution, seed);
          all.setup_and_first.push_back(problem.setup_seconds + o.first_path_seconds);
          tools::PlanOutcome alone = o;
          alone.seconds -= o.planner_setup_seconds;
          alone.first_path_seconds -= o.planner_setup_seconds;
          add(all.planning_alone, alone);
          record("ours", r, o, ours, all.ours);
        }
        if (run_stock)
          record("ompl_rrtconnect_fcl", r, bench::plan_stock(problem, *stock_checker, a.time_limit, a.resolution),
                 stock, all.stock);
      }
      if (show_progress()) std::cerr << "\r" << set << ": " << (i + 1) << "/" << requests.size() << std::flush;
    }
    if (show_progress()) std::cerr << "\n";
    print(set + " ours", ours);
    print(set + " OMPL RRTConnect+FCL " + a.stock_bvh, stock);
  }
  print_totals(all, a, run_ours, run_stock);
  return 0;
}

}  // namespace dmgplace::cli
