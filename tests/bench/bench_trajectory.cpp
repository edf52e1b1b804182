// Timing a joint path (Kunz & Stilman, runtime/motion/trajectory.hpp): random 7-dof paths of
// 2, 10 and 50 waypoints with Panda-like limits, corners blended within 0.01 rad. The counter
// duration_s is the mean trajectory duration (the same paths every run).
// Run: build/release/tests/bench_trajectory
#include <benchmark/benchmark.h>

#include <random>

#include "dmgplace/runtime/motion/trajectory.hpp"

using namespace dmgplace;

namespace {

std::vector<runtime::JointPath> random_paths(int waypoints, int count) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<runtime::JointPath> out(static_cast<std::size_t>(count));
  for (auto& path : out)
    for (int w = 0; w < waypoints; ++w) {
      std::vector<double> q(7);
      for (double& x : q) x = u(rng);
      path.push_back(q);
    }
  return out;
}

void BM_TimeParameterize(benchmark::State& st) {
  const auto paths = random_paths(int(st.range(0)), 16);
  runtime::JointLimits limits;
  limits.velocity = {2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61};
  limits.acceleration = {3.75, 1.875, 2.5, 3.125, 3.75, 5, 5};
  std::size_t i = 0;
  double duration = 0;
  for (auto _ : st) {
    const runtime::Trajectory t = runtime::time_parameterize(paths[i++ % paths.size()], limits);
    duration += t.duration();
    benchmark::DoNotOptimize(t.time.data());
  }
  st.counters["duration_s"] = duration / double(st.iterations());
}
BENCHMARK(BM_TimeParameterize)->Arg(2)->Arg(10)->Arg(50)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
