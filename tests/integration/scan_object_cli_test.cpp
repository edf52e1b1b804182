// Objects from the PCL sample scans in ../shared (a milk carton alone, a table scene with a mug)
// through the CLI: segmentation choices, sound artifacts, and a placement with the scanned mug.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace dmgplace::test {
namespace {

std::filesystem::path scans() {
  const auto shared = shared_datasets();
  return shared.empty() ? shared : shared / "scans/pcl";
}

TEST(ScanObjectCli, TheMilkCartonScannedAloneKeepsItsOwnFacesAndBakes) {
  if (scans().empty()) GTEST_SKIP() << "needs ../shared/datasets";
  TempDir dir;
  for (const char* method : {"poisson", "hull"}) {
    const auto r = run_cli(
        {"bake-object", scans() / "milk.pcd", "--reconstruct", method, "--json", "--out", dir / "milk.h5"}, false);
    ASSERT_EQ(r.exit_code, 0) << method << ": " << r.output;
    const auto j = nlohmann::json::parse(r.output);
    EXPECT_FALSE(j["scan"]["plane_removed"].get<bool>()) << "the carton's largest face is not a support";
    EXPECT_EQ(j["scan"]["clusters"].size(), 1u);
    EXPECT_GT(j["scan"]["seen_fraction"].get<double>(), 0.1);
    EXPECT_GT(j["artifact"]["placement_faces"].get<int>(), 0);
    EXPECT_EQ(run_cli({"validate", dir / "milk.h5"}).exit_code, 0);
  }
}

TEST(ScanObjectCli, TheTableSceneAsksForAClusterAndBakesTheChosenOne) {
  if (scans().empty()) GTEST_SKIP() << "needs ../shared/datasets";
  TempDir dir;
  const auto scene = scans() / "table_scene_mug_stereo_textured.pcd";
  const auto ask = run_cli({"bake-object", scene, "--out", dir / "x.h5"});
  EXPECT_EQ(ask.exit_code, 1);
  EXPECT_NE(ask.output.find("table_scene_mug_stereo_textured.pcd"), std::string::npos) << ask.output;
  EXPECT_NE(ask.output.find("choose one with --cluster N or --cluster-near"), std::string::npos) << ask.output;
  EXPECT_NE(ask.output.find("\n  0: "), std::string::npos) << ask.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.h5"));
  // Poisson on one view of the mug is a thin shell: refused with the way out named.
  const auto shell =
      run_cli({"bake-object", scene, "--crop", "-1,-1,0,1,1,1.5", "--cluster", "0", "--out", dir / "x.h5"});
  EXPECT_EQ(shell.exit_code, 1);
  EXPECT_NE(shell.output.find("--reconstruct hull"), std::string::npos) << shell.output;
  const auto r = run_cli({"bake-object", scene, "--crop", "-1,-1,0,1,1,1.5", "--cluster-near", "0.06,0.07,0.76",
                          "--reconstruct", "hull", "--json", "--out", dir / "mug.h5"},
                         false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_TRUE(j["scan"]["plane_removed"].get<bool>());
  EXPECT_EQ(j["scan"]["chosen_cluster"].get<int>(), 0);
  EXPECT_EQ(run_cli({"validate", dir / "mug.h5"}).exit_code, 0);
  // The header names the scan with its hash and the segmentation that was chosen.
  const auto obj = formats::load_object(dir / "mug.h5");
  ASSERT_FALSE(obj.header.inputs.empty());
  EXPECT_NE(obj.header.inputs.front().path.find("table_scene_mug"), std::string::npos);
  const auto params = nlohmann::json::parse(obj.header.parameters_json);
  EXPECT_EQ(params["reconstruct"], "hull");
  EXPECT_EQ(params["crop"].size(), 6u);
  EXPECT_EQ(params["cluster_near"].size(), 3u);
}

TEST(ScanObjectCli, TheScannedMugIsPlacedOnTheTable) {
  if (scans().empty()) GTEST_SKIP() << "needs ../shared/datasets";
  TempDir dir;
  const auto data = source_dir() / "datasets";
  ASSERT_EQ(run_cli({"bake-object", scans() / "table_scene_mug_stereo_textured.pcd", "--crop", "-1,-1,0,1,1,1.5",
                     "--cluster", "0", "--reconstruct", "hull", "--out", dir / "mug.h5"})
                .exit_code,
            0);
  ASSERT_EQ(run_cli({"bake-robot", data / "robots/dmgarm/dmgarm.urdf", "--srdf", data / "robots/dmgarm/dmgarm.srdf",
                     "--arm", "dmgarm_link0:dmgarm_tcp", "--out", dir / "arm.h5"})
                .exit_code,
            0);
  const std::string volume = builtin_volume("table");
  ASSERT_EQ(run_cli({"bake-env", data / "scenes/table.yaml", "--volume", volume, "--margin", "0.9", "--sdf-resolution",
                     "0.02", "--band", "0.25", "--out", dir / "table.h5"})
                .exit_code,
            0);
  const auto object = formats::load_object(dir / "mug.h5");
  ASSERT_GT(object.grasp_graph.size(), 0);
  const runtime::PlacementWorld world(formats::load_robot(dir / "arm.h5"), object,
                                      formats::load_environment(dir / "table.h5"));
  runtime::PlacementQuery q;
  q.q0 = Eigen::VectorXd(7);
  q.q0 << 0, -0.785, 0, -2.0, 0, 1.3, 0.785;
  const double* t = object.grasp_graph.tcp.data();  // held with the graph's first grasp
  q.g0 = Eigen::Translation3d(t[0], t[1], t[2]) * Eigen::Quaterniond(t[6], t[3], t[4], t[5]);
  q.seed = 1;
  runtime::PlacementPlanner planner(world, q);
  bool found = false;
  auto budget = runtime::stop_after_iterations(20000);
  const auto result =
      planner.run([&] { return found || budget(); }, [&](const runtime::PlacementSolution&) { found = true; });
  EXPECT_TRUE(found);
  EXPECT_FALSE(result.improvements.empty());
}

}  // namespace
}  // namespace dmgplace::test
