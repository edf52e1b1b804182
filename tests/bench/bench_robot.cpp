// Robot model speed (issue "Robot model"): FK + fast sphere check vs the FCL exact check of the
// same configurations, and IK, for the Panda in the MotionBenchMaker bookshelf scene.
// Run: build/release/tests/bench_robot   (needs ../shared/datasets)
// Environment: SDF_RES (grid cell, default 0.01 m), SPHERE_COUNT (most spheres per link, as
// bake-robot's --sphere-count; default its default, 6), NO_SELF_TABLES, NO_EXACT_PRIMITIVES.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <limits>
#include <random>

#include "analytic_sdf.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/runtime/robot/ik.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/robot/self_distance_tables.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"
#include "stock_fcl_checker.hpp"
#include "test_support.hpp"

using namespace dmgplace;

namespace {
struct World {
  RobotModel model;
  std::vector<formats::LinkSphere> spheres;
  std::unique_ptr<runtime::Kinematics> kin;
  Scene scene;
  std::shared_ptr<runtime::Grid3> sdf;
  std::vector<formats::SelfDistanceTable> tables;
  std::unique_ptr<runtime::SphereFieldChecker> fast;
  std::unique_ptr<runtime::ExactChecker> exact;
  std::unique_ptr<bench::StockFclChecker> stock;  // the bench-mbm baseline: mesh BVHs as MoveIt builds them
  std::vector<Eigen::VectorXd> configs;
};

World& world() {
  static World w = [] {
    World w;
    auto shared = test::shared_datasets();
    if (shared.empty()) throw std::runtime_error("bench_robot needs ../shared/datasets");
    tools::UrdfOptions o;
    o.package_paths.push_back(shared / "panda");
    w.model = tools::read_urdf(shared / "panda/moveit_resources_panda_description/urdf/panda.urdf", o);
    tools::apply_srdf(w.model, shared / "panda/panda_moveit_config/config/panda.srdf");
    tools::SphereCoverOptions cover;
    if (const char* n = std::getenv("SPHERE_COUNT")) cover.max_spheres = std::clamp(std::atoi(n), 1, 10000);
    for (std::size_t l = 0; l < w.model.links.size(); ++l)
      for (const auto& s : tools::cover_with_spheres(w.model.links[l].collision, cover))
        w.spheres.push_back({int(l), s.center, s.radius});
    w.kin = std::make_unique<runtime::Kinematics>(w.model, "panda_link0", "panda_hand");
    w.kin->set_joint_value("panda_finger_joint1", 0.04);
    w.scene = tools::load_scene(shared / "mbm_problems/bookshelf_small_panda/scene0001.yaml");
    w.sdf = test::analytic_sdf(w.scene,
                               Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.3), Eigen::Vector3d(1.6, 1.2, 1.7)),
                               std::getenv("SDF_RES") ? std::atof(std::getenv("SDF_RES")) : 0.01, 0.2);
    w.fast = std::make_unique<runtime::SphereFieldChecker>(*w.kin, w.spheres, w.sdf, 0.2);
    if (!std::getenv("NO_SELF_TABLES")) w.tables = tools::build_self_distance_tables(*w.kin, w.spheres);
    w.fast->set_self_tables(w.tables);
    // As bench-mbm runs it: undecided spheres settled by the scene's exact primitives.
    if (!std::getenv("NO_EXACT_PRIMITIVES"))
      w.fast->set_exact_obstacles(runtime::PrimitiveObstacles::from_scene(w.scene));
    w.exact = std::make_unique<runtime::ExactChecker>(*w.kin, w.scene);
    w.stock = std::make_unique<bench::StockFclChecker>(*w.kin, w.scene);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 4096; ++i) {
      Eigen::VectorXd q(7);
      for (int j = 0; j < 7; ++j) q[j] = w.kin->lower()[j] + u(rng) * (w.kin->upper()[j] - w.kin->lower()[j]);
      w.configs.push_back(q);
    }
    std::cerr << "panda spheres: " << w.spheres.size() << "\n";
    return w;
  }();
  return w;
}

void BM_FkPlusFastSphereCheck(benchmark::State& st) {
  auto& w = world();
  std::size_t i = 0;
  long free = 0;
  for (auto _ : st) {
    free += w.fast->is_free(w.configs[i++ & 4095]);
  }
  st.SetItemsProcessed(st.iterations());
  st.counters["free_fraction"] = double(free) / double(st.iterations());
}
BENCHMARK(BM_FkPlusFastSphereCheck);

// Issue 20: the same configurations 8 per call (SphereFieldChecker::free_lanes); items are
// configurations. Arg 0: the portable path, 1: AVX2 where the CPU has it.
void BM_FkPlusFastSphereCheckLanes8(benchmark::State& st) {
  auto& w = world();
  runtime::force_simd_path(st.range(0) ? runtime::SimdPath::Avx2 : runtime::SimdPath::Portable);
  std::size_t i = 0;
  long free = 0;
  const double* q[runtime::LinkPoseLanesD::kLanes];
  for (auto _ : st) {
    for (int k = 0; k < runtime::LinkPoseLanesD::kLanes; ++k) q[k] = w.configs[i++ & 4095].data();
    free += __builtin_popcount(w.fast->free_lanes(q));
  }
  st.SetItemsProcessed(st.iterations() * runtime::LinkPoseLanesD::kLanes);
  st.counters["free_fraction"] = double(free) / double(st.iterations() * runtime::LinkPoseLanesD::kLanes);
  st.counters["margin_um"] = 1e6 * w.fast->lane_margin();
  st.SetLabel(runtime::to_string(runtime::simd_path()));
  runtime::force_simd_path(runtime::SimdPath::Avx2);
}
BENCHMARK(BM_FkPlusFastSphereCheckLanes8)->Arg(0)->Arg(1);

// Forward kinematics alone: one configuration per call against 8 per call.
void BM_Fk(benchmark::State& st) {
  auto& w = world();
  std::vector<Eigen::Isometry3d> poses;
  std::size_t i = 0;
  for (auto _ : st) {
    w.kin->link_poses(w.configs[i++ & 4095], poses);
    benchmark::DoNotOptimize(poses.data());
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_Fk);

template <class T>
void fk_lanes(benchmark::State& st) {
  auto& w = world();
  runtime::LinkPoseLanes<T> poses;
  std::size_t i = 0;
  const double* q[runtime::LinkPoseLanesD::kLanes];
  for (auto _ : st) {
    for (int k = 0; k < runtime::LinkPoseLanesD::kLanes; ++k) q[k] = w.configs[i++ & 4095].data();
    w.kin->lanes().link_poses(q, poses);
    benchmark::DoNotOptimize(poses.pose.data());
  }
}
// Arguments: the SIMD path (0 portable, 1 AVX2 where the CPU has it); the precision (0 doubles,
// 1 floats, as the lane sphere check runs it).
void BM_FkLanes8(benchmark::State& st) {
  runtime::force_simd_path(st.range(0) ? runtime::SimdPath::Avx2 : runtime::SimdPath::Portable);
  if (st.range(1)) fk_lanes<float>(st);
  else fk_lanes<double>(st);
  st.SetItemsProcessed(st.iterations() * runtime::LinkPoseLanesD::kLanes);
  st.SetLabel(runtime::to_string(runtime::simd_path()));
  runtime::force_simd_path(runtime::SimdPath::Avx2);
}
BENCHMARK(BM_FkLanes8)->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1});

// check_along on the configurations the fast layer proves free (a planner's motions are mostly
// free), unit random directions; the argument is `enough` in mrad (0: unlimited).
void BM_FkPlusCertifiedCheck(benchmark::State& st) {
  auto& w = world();
  static std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> cases = [&] {
    std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> out;
    std::mt19937_64 rng(2);
    std::normal_distribution<double> g(0, 1);
    for (const auto& q : w.configs)
      if (w.fast->is_free(q)) {
        Eigen::VectorXd d(q.size());
        for (Eigen::Index j = 0; j < d.size(); ++j) d[j] = g(rng);
        out.emplace_back(q, d.normalized());
      }
    return out;
  }();
  const double enough = st.range(0) > 0 ? 1e-3 * double(st.range(0)) : std::numeric_limits<double>::infinity();
  std::size_t i = 0;
  double certified = 0;
  for (auto _ : st) {
    const auto& [q, d] = cases[i++ % cases.size()];
    certified += std::min(1.0, w.fast->check_along(q, d, enough).free_distance);
  }
  st.SetItemsProcessed(st.iterations());
  st.counters["mean_certified"] = certified / double(st.iterations());
}
BENCHMARK(BM_FkPlusCertifiedCheck)->Arg(0)->Arg(20);

// Issue 20: a 0.5 rad motion checked at 0.01 rad as the planners check it (make_arm_space over
// the two-layer checker: certificates, lane proofs near obstacles), from free states in random
// directions. Items: motions.
void BM_MotionCheckHalfRadian(benchmark::State& st) {
  auto& w = world();
  static const Scene open = [] {
    Scene s;
    s.objects.push_back({"far", {test::box_shape(Eigen::Vector3d(0.1, 0.1, 0.1), Eigen::Vector3d(3, 3, 3))}});
    return s;
  }();
  const Scene& scene = st.range(0) == 0 ? open : w.scene;
  runtime::SphereFieldChecker fast(
      *w.kin, w.spheres,
      test::analytic_sdf(scene, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.3), Eigen::Vector3d(1.6, 1.2, 1.7)),
                         0.02, 0.2),
      0.2);
  fast.set_self_tables(w.tables);
  fast.set_exact_obstacles(runtime::PrimitiveObstacles::from_scene(scene));
  runtime::TwoLayerChecker checker(fast, runtime::ExactChecker(*w.kin, scene));
  checker.set_exact_gaps(st.range(1) != 0);  // proven gaps for flagged links (hulls), or FCL's yes/no
  auto si = runtime::make_arm_space(*w.kin, checker, 0.01);
  std::vector<std::pair<ompl::base::State*, ompl::base::State*>> cases;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0, 1);
  for (const auto& q : w.configs) {
    if (cases.size() == 512) break;
    // Starts the fast layer proves free (the series), or every FCL-free one, so that
    // sphere models are compared on the same motions.
    if (!(st.range(2) ? checker.is_free(q) : checker.fast().is_free(q))) continue;
    Eigen::VectorXd d(q.size());
    for (Eigen::Index j = 0; j < d.size(); ++j) d[j] = g(rng);
    const Eigen::VectorXd b = (q + 0.5 * d.normalized()).cwiseMax(w.kin->lower()).cwiseMin(w.kin->upper());
    auto* s1 = si->allocState();
    auto* s2 = si->allocState();
    si->getStateSpace()->copyFromReals(s1, std::vector<double>(q.data(), q.data() + q.size()));
    si->getStateSpace()->copyFromReals(s2, std::vector<double>(b.data(), b.data() + b.size()));
    cases.emplace_back(s1, s2);
  }
  std::size_t i = 0;
  long valid = 0;
  for (auto _ : st) {
    const auto& [s1, s2] = cases[i++ % cases.size()];
    valid += si->checkMotion(s1, s2);
  }
  for (auto& [s1, s2] : cases) {
    si->freeState(s1);
    si->freeState(s2);
  }
  st.SetItemsProcessed(st.iterations());
  st.counters["valid_fraction"] = double(valid) / double(st.iterations());
  st.counters["states_per_motion"] = double(checker.counters().fast.load()) / double(st.iterations());
  st.counters["exact_per_motion"] =
      double(checker.counters().exact_pairs.load() + checker.counters().exact_full.load()) / double(st.iterations());
}
// Arguments: scene (0 open space, 1 bookshelf), exact gaps (1 on, as planners run it; 0 off),
// starts (0 proven free by the fast layer, 1 free by FCL).
BENCHMARK(BM_MotionCheckHalfRadian)
    ->Args({0, 1, 0})
    ->Args({1, 1, 0})
    ->Args({0, 0, 0})
    ->Args({1, 0, 0})
    ->Args({0, 1, 1})
    ->Args({1, 1, 1});

void BM_TwoLayerCheck(benchmark::State& st) {
  auto& w = world();
  runtime::TwoLayerChecker c(*w.fast, *w.exact);
  std::size_t i = 0;
  for (auto _ : st) benchmark::DoNotOptimize(c.is_free(w.configs[i++ & 4095]));
  st.SetItemsProcessed(st.iterations());
  st.counters["full_exact_fraction"] = double(c.counters().exact_full.load()) / double(st.iterations());
}
BENCHMARK(BM_TwoLayerCheck);

// One flagged link's proven clearance to the bookshelf, as a certified check asks it: the hand's
// hull (argument 0) or link 4's (1) against every shelf primitive, nearest bounding balls first.
void BM_HullGapToScene(benchmark::State& st) {
  auto& w = world();
  const int link = w.kin->model().link_index(st.range(0) == 0 ? "panda_hand" : "panda_link4");
  std::vector<std::vector<Eigen::Isometry3d>> poses(256);
  for (std::size_t k = 0; k < poses.size(); ++k) w.kin->link_poses(w.configs[k], poses[k]);
  std::size_t i = 0;
  long positive = 0;
  for (auto _ : st) {
    const double g = w.exact->link_environment_gap(poses[i++ & 255], link);
    positive += g > 0;
    benchmark::DoNotOptimize(g);
  }
  st.SetItemsProcessed(st.iterations());
  st.counters["proven_fraction"] = double(positive) / double(st.iterations());
}
BENCHMARK(BM_HullGapToScene)->Arg(0)->Arg(1);

// Argument 0: our exact layer (OBB mesh hierarchies); 1: bench-mbm's stock baseline, OBBRSS as
// MoveIt builds them (FCL then fits an OBB to each box or cylinder obstacle by eigen-decomposition
// on every mesh-vs-primitive test).
void BM_FclMeshCheck(benchmark::State& st) {
  auto& w = world();
  std::size_t i = 0;
  if (st.range(0) == 0)
    for (auto _ : st) benchmark::DoNotOptimize(w.exact->is_free(w.configs[i++ & 4095]));
  else
    for (auto _ : st) benchmark::DoNotOptimize(w.stock->is_free(w.configs[i++ & 4095]));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_FclMeshCheck)->Arg(0)->Arg(1);

void BM_IkRandomReachablePose(benchmark::State& st) {
  auto& w = world();
  runtime::IkSolver ik(*w.kin);
  std::mt19937_64 rng(5);
  std::size_t i = 0;
  long ok = 0;
  std::vector<double> seconds;
  for (auto _ : st) {
    st.PauseTiming();
    const Eigen::Isometry3d target = w.kin->tip_pose(w.configs[i & 4095]);
    const Eigen::VectorXd seed = w.configs[(i * 7 + 3) & 4095];
    ++i;
    st.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    ok += ik.solve(target, seed, rng).success;
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(seconds.begin(), seconds.end());
  st.counters["success_rate"] = double(ok) / double(st.iterations());
  st.counters["median_us"] = seconds.empty() ? 0.0 : 1e6 * seconds[seconds.size() / 2];
}
BENCHMARK(BM_IkRandomReachablePose)->Unit(benchmark::kMicrosecond);
}  // namespace

BENCHMARK_MAIN();
