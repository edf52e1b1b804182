// Environment analysis speed (issue "Environment analysis"): the band-limited Embree distance
// grid of a ~10k-triangle scene over a 2 m cube at 1 cm (8M samples) on one core, placement
// regions of the MotionBenchMaker kitchen, and trilinear Grid3 lookups.
// Run: build/release/tests/bench_env   (the kitchen case needs ../shared/datasets)
#include <benchmark/benchmark.h>

#include <random>

#include "dmgplace/runtime/environment/environment_model.hpp"
#include "dmgplace/tools/environment/distance_field.hpp"
#include "dmgplace/tools/environment/geometry_regions.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "test_support.hpp"

using namespace dmgplace;

namespace {

// A floor, shelves and 12 spheres of 960 triangles each: about 11.6k triangles in a 2 m cube.
Scene ten_k_scene() {
  Scene s;
  auto add = [&s](ShapeType t, Eigen::Vector3d size, Eigen::Vector3d at) {
    Shape sh;
    sh.type = t;
    sh.size = size;
    sh.origin.translation() = at;
    s.objects.push_back({"o" + std::to_string(s.objects.size()), {sh}});
  };
  add(ShapeType::Box, {2, 2, 0.02}, {0, 0, -0.99});
  for (int b = 0; b < 4; ++b) add(ShapeType::Box, {0.4, 1.6, 0.02}, {-0.7 + 0.45 * b, 0, -0.6 + 0.35 * b});
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  for (int k = 0; k < 12; ++k) add(ShapeType::Sphere, {0.08, 0, 0}, {u(rng), u(rng), u(rng)});
  return s;
}

const Eigen::AlignedBox3d kCube(Eigen::Vector3d::Constant(-1.0), Eigen::Vector3d::Constant(1.0));

void BM_DistanceGrid_10kTriangles_2mCube_1cm(benchmark::State& state) {
  const tools::EnvironmentGeometry geo = tools::make_environment_geometry(ten_k_scene(), 32);
  std::size_t triangles = 0;
  for (const auto& m : geo.meshes) triangles += std::size_t(m.triangles.rows());
  const tools::EmbreeScene scene(geo);
  const tools::GridSpec spec = tools::grid_covering(kCube, 0.01);
  for (auto _ : state) {
    auto f = tools::distance_field(scene, spec, 0.1, 1);
    benchmark::DoNotOptimize(f.values.data());
  }
  state.counters["triangles"] = double(triangles);
  state.counters["samples"] = double(spec.size());
}
BENCHMARK(BM_DistanceGrid_10kTriangles_2mCube_1cm)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3);

void BM_Regions_MbmKitchen(benchmark::State& state) {
  const auto shared = test::shared_datasets();
  if (shared.empty()) {
    state.SkipWithError("needs ../shared/datasets");
    return;
  }
  tools::SceneLoadOptions load;
  load.urdf.package_paths.push_back(shared / "env");
  const Scene kitchen = tools::load_scene(shared / "env/motion_bench_maker/configs/scenes/kitchen/kitchen.urdf", load);
  const Eigen::AlignedBox3d v(Eigen::Vector3d(-0.5, -1.5, 0.0), Eigen::Vector3d(1.5, 1.5, 2.0));
  std::size_t regions = 0;
  for (auto _ : state) {
    // Everything regions need: tessellation, BVH, one ray per 1 cm cell, levels, components, splits.
    const tools::EnvironmentGeometry geo = tools::make_environment_geometry(kitchen, 32);
    const tools::EmbreeScene scene(geo);
    tools::RegionOptions o;
    const tools::CellGrid grid = tools::cell_grid(v, o.resolution);
    regions = tools::build_regions(grid, tools::geometry_surface_samples(scene, v, grid, o), o).size();
  }
  state.counters["regions"] = double(regions);
}
BENCHMARK(BM_Regions_MbmKitchen)->Unit(benchmark::kMillisecond);

// Lookups over a 2 m cube at 1 cm (8M samples, 32 MB). Arg 0: uniformly random points (every
// lookup a cache miss); arg 1: a random walk with 1 cm steps, like the spheres of a moving arm.
void BM_Grid3TrilinearLookups(benchmark::State& state) {
  runtime::Grid3 g(Eigen::Vector3d::Constant(-1.0), 0.01, {201, 201, 201});
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> uv(-0.1f, 0.1f);
  for (auto& v : g.values()) v = uv(rng);
  std::uniform_real_distribution<double> u(-0.99, 0.99), step(-0.01, 0.01);
  std::vector<Eigen::Vector3d> pts(1 << 16);
  Eigen::Vector3d walk = Eigen::Vector3d::Zero();
  for (auto& p : pts) {
    walk = (walk + Eigen::Vector3d(step(rng), step(rng), step(rng))).cwiseMax(-0.99).cwiseMin(0.99);
    p = state.range(0) == 0 ? Eigen::Vector3d(u(rng), u(rng), u(rng)) : walk;
  }
  std::size_t n = 0;
  double sum = 0;
  Eigen::Vector3d grad;
  for (auto _ : state) {
    if (state.range(1))
      for (const auto& p : pts) sum += g.sample(p, grad) + grad.x();
    else
      for (const auto& p : pts) sum += g.sample(p);
    n += pts.size();
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(std::int64_t(n));
}
// Args: points (0 random, 1 walk), with gradient (0/1).
BENCHMARK(BM_Grid3TrilinearLookups)->Args({0, 0})->Args({1, 0})->Args({1, 1});

}  // namespace

BENCHMARK_MAIN();
