// World::load speed (issue 61): the demo's world (dmgarm, bottle, cabinet) and the shared kitchen
// world (Panda, YCB mustard bottle, MotionBenchMaker kitchen), artifacts, checks and all. Targets:
// demo < 20 ms, kitchen < 50 ms median. Run after `scripts/demo` and `scripts/bake-shared`:
//   build/release/tests/bench_world_load [--benchmark_repetitions=15]
// DMGPLACE_DEMO_ARTIFACTS and DMGPLACE_SHARED_ARTIFACTS name other folders.
#include <benchmark/benchmark.h>

#include <cstdlib>

#include "dmgplace/runtime.hpp"
#include "test_support.hpp"

using namespace dmgplace;
namespace fs = std::filesystem;

namespace {

fs::path folder(const char* variable, const char* fallback) {
  const char* v = std::getenv(variable);
  return v && *v ? fs::path(v) : test::source_dir() / fallback;
}

void load_world(benchmark::State& state, const fs::path& dir, const char* robot, const char* object, const char* env) {
  for (const char* f : {robot, object, env})
    if (!fs::exists(dir / f)) {
      state.SkipWithError(
          ((dir / f).string() + " is missing: bake it first (scripts/demo, scripts/bake-shared)").c_str());
      return;
    }
  for (auto _ : state) {
    auto world = World::load(dir / robot, dir / object, dir / env);
    benchmark::DoNotOptimize(world.get());
  }
}

void BM_LoadDemoWorld(benchmark::State& state) {
  load_world(state, folder("DMGPLACE_DEMO_ARTIFACTS", "out/demo/artifacts"), "dmgarm.h5", "bottle.h5", "cabinet.h5");
}
BENCHMARK(BM_LoadDemoWorld)->Unit(benchmark::kMillisecond)->Iterations(15);

void BM_LoadKitchenWorld(benchmark::State& state) {
  load_world(state, folder("DMGPLACE_SHARED_ARTIFACTS", "out/shared/artifacts"), "panda.h5", "mustard.h5",
             "kitchen.h5");
}
BENCHMARK(BM_LoadKitchenWorld)->Unit(benchmark::kMillisecond)->Iterations(15);

}  // namespace
BENCHMARK_MAIN();
