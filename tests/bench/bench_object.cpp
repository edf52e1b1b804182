// Object analysis speed (issue "Object analysis"): the whole bake of the 16k-triangle YCB mustard
// bottle (mesh reading, mass, placement faces, DMG) on one core, and the reachable-grasp Dijkstra.
// Targets: bake < 2 s, Dijkstra < 5 ms. Run: build/release/tests/bench_object (needs ../shared/datasets)
#include <benchmark/benchmark.h>

#include <map>

#include <stdexcept>

#include "dmgplace/runtime/grasp/reachable_grasps.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/object/dmg_builder.hpp"
#include "dmgplace/tools/object/gripper_model.hpp"
#include "dmgplace/tools/object/mass_properties.hpp"
#include "dmgplace/tools/object/placement_faces.hpp"
#include "dmgplace/tools/scan/scan_object.hpp"
#include "test_support.hpp"

using namespace dmgplace;

namespace {

std::filesystem::path ycb(const std::string& name) {
  const auto shared = test::shared_datasets();
  if (shared.empty()) throw std::runtime_error("bench_object needs ../shared/datasets");
  return shared / "objects/ycb" / (name + "_textured.obj");
}
std::filesystem::path mustard() { return ycb("006_mustard_bottle"); }

formats::ObjectArtifact bake(const std::string& name = "006_mustard_bottle") {
  formats::ObjectArtifact a;
  a.mesh = tools::read_mesh(ycb(name));
  a.mass = tools::compute_mass_properties(a.mesh, 0, "mustard");
  a.placement = tools::compute_placement_faces(a.mesh, a.mass.com, {}, "mustard");
  a.dmg = tools::build_dmg(a.mesh, tools::default_gripper(), {}, "mustard");
  a.grasp_graph = formats::build_grasp_graph_table(a.dmg);
  return a;
}

void BM_BakeObjectMustard(benchmark::State& state) {
  for (auto _ : state) {
    auto a = bake();
    benchmark::DoNotOptimize(a.dmg.nodes.data());
    state.counters["triangles"] = double(a.mesh.triangles.rows());
    state.counters["nodes"] = double(a.dmg.nodes.size());
    state.counters["edges"] = double(a.dmg.edges.size());
  }
}
BENCHMARK(BM_BakeObjectMustard)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_BuildDmgOnlyMustard(benchmark::State& state) {
  const auto mesh = tools::read_mesh(mustard());
  for (auto _ : state) {
    auto d = tools::build_dmg(mesh, tools::default_gripper(), {}, "mustard");
    benchmark::DoNotOptimize(d.nodes.data());
  }
}
BENCHMARK(BM_BuildDmgOnlyMustard)->Unit(benchmark::kMillisecond)->Iterations(3);

// Reachable grasps from the middle grasp state of an object's graph. The cracker box (broad flat
// sides) has the larger grasp graph: the harder Dijkstra case.
void BM_ReachableGrasps(benchmark::State& state, const char* object) {
  // Benchmark functions run several times: bake each object once.
  static std::map<std::string, runtime::GraspGraph> graphs;
  if (!graphs.count(object)) graphs.emplace(object, runtime::GraspGraph(bake(object)));
  const runtime::GraspGraph& graph = graphs.at(object);
  if (graph.size() == 0) {
    state.SkipWithError("no grasps");
    return;
  }
  const Eigen::Isometry3d initial = graph.tcp_pose(graph.size() / 2);
  std::size_t reached = 0;
  for (auto _ : state) {
    auto r = runtime::reachable_grasps(graph, initial);
    reached = r.grasps.size();
    benchmark::DoNotOptimize(r.grasps.data());
  }
  state.counters["states"] = double(graph.size());
  state.counters["reached"] = double(reached);
}
BENCHMARK_CAPTURE(BM_ReachableGrasps, mustard, "006_mustard_bottle")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReachableGrasps, cracker_box, "003_cracker_box")->Unit(benchmark::kMillisecond);

void BM_DijkstraOnlyMustard(benchmark::State& state) {
  static const auto obj = bake();
  static const runtime::GraspGraph graph(obj);
  if (graph.size() == 0) {
    state.SkipWithError("no grasps");
    return;
  }
  for (auto _ : state) {
    auto r = runtime::dijkstra(graph.graph(), graph.size() / 2);
    benchmark::DoNotOptimize(r.cost.data());
  }
}
BENCHMARK(BM_DijkstraOnlyMustard)->Unit(benchmark::kMillisecond);

// Grasp graph at load time: reading the baked table into the runtime's graph, against deriving it
// from the DMG as loads did before it was stored (docs/formats.md reports the pair).
const formats::ObjectArtifact& cracker_box() {
  static const auto obj = bake("003_cracker_box");
  return obj;
}

void BM_GraspGraphFromStoredTable(benchmark::State& state) {
  const auto& obj = cracker_box();
  for (auto _ : state) {
    runtime::GraspGraph g(obj);
    benchmark::DoNotOptimize(g.graph().targets.data());
  }
  state.counters["states"] = double(obj.grasp_graph.size());
}
BENCHMARK(BM_GraspGraphFromStoredTable)->Unit(benchmark::kMillisecond);

void BM_GraspGraphRebuiltFromDmg(benchmark::State& state) {
  const auto& obj = cracker_box();
  for (auto _ : state) {
    runtime::GraspGraph g(obj.dmg, formats::build_grasp_graph_table(obj.dmg));
    benchmark::DoNotOptimize(g.graph().targets.data());
  }
}
BENCHMARK(BM_GraspGraphRebuiltFromDmg)->Unit(benchmark::kMillisecond);

// The whole gated load (read, checksums, every semantic check including the graph's) + the graph.
void BM_LoadObjectWithGraspGraph(benchmark::State& state) {
  const auto file = std::filesystem::temp_directory_path() / "dmgplace_bench_cracker_box.h5";
  formats::save_object(cracker_box(), file);
  for (auto _ : state) {
    const auto obj = formats::load_object(file);
    runtime::GraspGraph g(obj);
    benchmark::DoNotOptimize(g.graph().targets.data());
  }
  std::filesystem::remove(file);
}
BENCHMARK(BM_LoadObjectWithGraspGraph)->Unit(benchmark::kMillisecond);

// Scan to object (issue 21's target: < 3 s for a 300k-point scan): segmentation, reconstruction,
// mass, placement faces, DMG and grasp graph, as `bake-object SCAN.pcd` does them.
void BM_ScanToObject(benchmark::State& state, const char* file, bool crop, tools::Reconstruction method) {
  tools::ScanObjectOptions o;
  o.reconstruct.method = method;
  if (crop) {
    o.segment.crop = Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(1, 1, 1.5));
    o.segment.cluster = 0;
  }
  const auto path = test::shared_datasets() / "scans/pcl" / file;
  std::size_t points = 0;
  for (auto _ : state) {
    const auto scan = tools::object_from_scans({path}, o);
    formats::ObjectArtifact a;
    a.mesh = scan.mesh;
    a.mass = tools::compute_mass_properties(a.mesh, 0, file);
    a.placement = tools::compute_placement_faces(a.mesh, a.mass.com, {}, file);
    a.dmg = tools::build_dmg(a.mesh, tools::default_gripper(), {}, file);
    a.grasp_graph = formats::build_grasp_graph_table(a.dmg);
    points = scan.segmented.input_points;
    benchmark::DoNotOptimize(a.grasp_graph.targets.data());
  }
  state.counters["scan_points"] = double(points);
}
BENCHMARK_CAPTURE(BM_ScanToObject, milk_poisson, "milk.pcd", false, tools::Reconstruction::Poisson)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_ScanToObject, milk_hull, "milk.pcd", false, tools::Reconstruction::Hull)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_ScanToObject, table_scene_mug_hull, "table_scene_mug_stereo_textured.pcd", true,
                  tools::Reconstruction::Hull)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
