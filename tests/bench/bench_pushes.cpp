// The pushes a second arm would need (issue 60): the built-in dual-arm case
// (datasets/queries/dual_cabinet_bottle_blocked.yaml) solved without its pusher, as
// `place --pusher none` does, then the best solution's in-hand actions planned for the pusher.
// Per seed: whether every action is executable (counter `executable`), the planning time per
// action (target < 50 ms), and the pusher's timed duration against its path's joint-space length.
// Run after `scripts/demo` (DMGPLACE_DEMO_ARTIFACTS names another artifact folder;
// DMGPLACE_PUSH_SEARCH_SECONDS the search's seconds per seed, default 5):
//   build/release/tests/bench_pushes
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/motion/arm_timing.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"
#include "dmgplace/runtime/placement/push_planner.hpp"
#include "dmgplace/tools/placement/placement_query_file.hpp"
#include "test_support.hpp"

using namespace dmgplace;
namespace fs = std::filesystem;

namespace {

double env_number(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atof(v) : fallback;
}

void BM_PushesOfTheBestSolutionWithoutAPusher(benchmark::State& state) {
  const char* dir = std::getenv("DMGPLACE_DEMO_ARTIFACTS");
  const fs::path artifacts = dir && *dir ? fs::path(dir) : test::source_dir() / "out/demo/artifacts";
  if (!fs::exists(artifacts / "dmgdual.h5")) {
    state.SkipWithError((artifacts / "dmgdual.h5").string().append(" is missing: run scripts/demo first").c_str());
    return;
  }
  const fs::path file = test::source_dir() / "datasets/queries/dual_cabinet_bottle_blocked.yaml";
  tools::PlacementQueryFile f = tools::read_placement_query(file, artifacts);
  const formats::RobotArtifact robot = formats::load_robot(f.robot);
  runtime::PlacementWorld world(robot, formats::load_object(f.object), formats::load_environment(f.environment), -1,
                                tools::world_joint_values(f, robot.model));
  f.query.q0 = tools::resolve_start(f, world.kinematics());
  const runtime::PusherSpec spec = *f.query.pusher;
  runtime::PlacementQuery q = f.query;
  q.pusher.reset();  // as `place --pusher none`
  q.seed = std::uint64_t(state.range(0));
  const double search = env_number("DMGPLACE_PUSH_SEARCH_SECONDS", 5.0);
  for (auto _ : state) {
    runtime::PlacementPlanner planner(world, q);
    const runtime::PlacementResult r = planner.run(runtime::stop_after_seconds(search));
    if (!r.solved()) {
      state.counters["solved"] = 0;
      continue;
    }
    const auto& best = r.best();
    runtime::PushPlanner pusher(world, spec, q.q0, q.options.motion_resolution, q.seed, file.string());
    const auto t0 = std::chrono::steady_clock::now();
    const auto plans = pusher.plan(best.in_hand, runtime::TimingOptions{});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double duration = 0, length = 0;
    if (plans)
      for (const runtime::PushPlan& p : *plans) {
        duration += p.trajectory.duration();
        for (std::size_t i = 1; i < p.path.size(); ++i)
          length += (Eigen::Map<const Eigen::VectorXd>(p.path[i].data(), Eigen::Index(p.path[i].size())) -
                     Eigen::Map<const Eigen::VectorXd>(p.path[i - 1].data(), Eigen::Index(p.path[i - 1].size())))
                        .norm();
      }
    state.counters["solved"] = 1;
    state.counters["objective"] = best.objective;
    state.counters["actions"] = double(best.in_hand.size());
    state.counters["executable"] = plans ? 1 : 0;
    // Actions planned before the answer (the first that fails ends it).
    state.counters["ms_per_action"] = pusher.planned() ? 1e3 * seconds / double(pusher.planned()) : 0;
    state.counters["push_s"] = duration;
    state.counters["push_rad"] = length;
  }
}
BENCHMARK(BM_PushesOfTheBestSolutionWithoutAPusher)->DenseRange(1, 5)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
BENCHMARK_MAIN();
