#include "dmgplace/tools/experiment/experiment_runner.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <mutex>
#include <ostream>
#include <thread>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime.hpp"
#include "dmgplace/tools/experiment/experiment_results.hpp"
#include "dmgplace/tools/placement/placement_report.hpp"

namespace dmgplace::tools {
namespace {
using Clock = std::chrono::steady_clock;

struct Task {
  const ExperimentProblem* problem;
  runtime::PlacementVariant variant;
  int seed;
};

// Worlds are read-only once built: runs of the same artifacts share one.
class WorldCache {
 public:
  std::shared_ptr<const World> get(const PlacementQueryFile& q) {
    std::string key = q.robot.string() + "|" + q.object.string() + "|" + q.environment.string() + "|" +
                      (q.query.g0_opening ? std::to_string(*q.query.g0_opening) : std::string("-"));
    for (const auto& [name, value] : q.start_named) key += "|" + name + "=" + std::to_string(value);
    std::lock_guard<std::mutex> lock(mutex_);
    auto& w = worlds_[key];
    if (!w) {
      auto robot = formats::load_robot(q.robot);
      const auto joints = world_joint_values(q, robot.model);
      w = World::from_artifacts(std::move(robot), formats::load_object(q.object),
                                formats::load_environment(q.environment), q.query.g0_opening, joints);
    }
    return w;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const World>> worlds_;
};

std::string clock_text(double s) {
  std::ostringstream o;
  const long t = long(std::lround(s));
  if (t >= 3600) o << t / 3600 << "h";
  o << std::setw(t >= 3600 ? 2 : 1) << std::setfill('0') << (t / 60) % 60 << "m" << std::setw(2) << t % 60 << "s";
  return o.str();
}
}  // namespace

ExperimentTotals run_experiment(const ExperimentSpec& spec, const ExperimentOptions& o, std::ostream& progress) {
  const int runs = o.runs > 0 ? o.runs : (o.quick ? spec.quick_runs : spec.runs);
  const double limit = o.time_limit >= 0 ? o.time_limit : (o.quick ? spec.quick_time_limit : spec.time_limit);
  const auto artifacts = o.artifacts.empty() ? spec.artifacts : o.artifacts;
  std::vector<Task> todo;
  ExperimentTotals totals;
  for (const auto& p : spec.problems)
    for (auto v : p.variants)
      for (int seed = 1; seed <= runs; ++seed) {
        ++totals.planned;
        if (std::filesystem::exists(run_folder(o.out, p.name, runtime::to_string(v), seed) / "result.json"))
          ++totals.skipped;
        else todo.push_back({&p, v, seed});
      }
  // Queries are read up front so a bad one fails before hours of runs.
  std::map<const ExperimentProblem*, PlacementQueryFile> queries;
  for (const auto& p : spec.problems) queries[&p] = read_placement_query(p.query, artifacts);
  progress << spec.name << ": " << totals.planned << " runs (" << totals.skipped << " already done), " << limit
           << " s each, " << o.jobs << " at a time\n";
  WorldCache worlds;
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0}, solved{0};
  std::mutex out_mutex;
  std::string failure;
  const auto t0 = Clock::now();
  auto worker = [&] {
    for (std::size_t i = next++; i < todo.size(); i = next++) {
      const Task& t = todo[i];
      try {
        PlacementQueryFile q = queries.at(t.problem);
        q.query.seed = std::uint64_t(t.seed);
        q.query.variant = t.variant;
        if (spec.threads) q.query.options.threads = *spec.threads;  // else the query's own (0: deterministic)
        q.time_limit = limit;
        const auto world = worlds.get(q);
        q.query.q0 = resolve_start(q, world->kinematics());
        const auto result = place(*world, q.query, stop_after_seconds(limit));
        write_placement_result(run_folder(o.out, t.problem->name, runtime::to_string(t.variant), t.seed), q, result,
                               world->kinematics());
        solved += result.solved();
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(out_mutex);
        if (failure.empty()) failure = e.what();
        next = todo.size();  // stop handing out runs
        return;
      }
      const int d = ++done;
      const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(out_mutex);
      progress << (o.redraw_progress ? "\r[" : "[") << d << "/" << todo.size() << "] " << t.problem->name << " "
               << runtime::to_string(t.variant) << " seed " << t.seed << "  elapsed " << clock_text(elapsed) << "  ETA "
               << clock_text(elapsed / d * double(todo.size() - std::size_t(d))) << (o.redraw_progress ? "   " : "\n")
               << std::flush;
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, o.jobs); ++j) pool.emplace_back(worker);
  for (auto& th : pool) th.join();
  if (!todo.empty() && o.redraw_progress) progress << "\n";
  if (!failure.empty()) throw Error(spec.path.string(), "", "a run failed: " + failure);
  totals.ran = done;
  const auto all = read_runs(o.out);
  for (const auto& r : all) totals.solved += r.solved;
  write_summary(o.out / "summary.csv", all, spec.report_times);
  return totals;
}

}  // namespace dmgplace::tools
