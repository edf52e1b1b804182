// End-to-end object analysis: bake-object with the DMG options and a gripper file, `grasps`, and
// the real shared data (YCB objects, the original DMG's tray).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "dmgplace/formats/object_artifact.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using dmgplace::test::TempDir;

namespace {

// stderr merged into the output, or dropped when `merge_stderr` is false.
dmgplace::test::ProcessResult run(const std::vector<dmgplace::test::Arg>& args, bool merge_stderr = true) {
  return dmgplace::test::run_cli(args, merge_stderr);
}

}  // namespace

TEST(ObjectCli, GripperFileAndGraspsJson) {
  TempDir dir;
  ASSERT_EQ(run({"make-objects", "--out", dir.path()}).exit_code, 0);
  const fs::path gripper = dmgplace::test::source_dir() / "datasets/grippers/dmgarm_hand.yaml";
  auto bake = run({"bake-object", dir / "eraser.stl", "--gripper", gripper, "--seed-resolution", "0.012",
                   "--angle-step", "20", "--out", dir / "eraser.h5"});
  ASSERT_EQ(bake.exit_code, 0) << bake.output;
  const auto obj = dmgplace::formats::load_object(dir / "eraser.h5");
  EXPECT_EQ(obj.dmg.angle_count(), 18);
  EXPECT_EQ(obj.placement.faces.size(), 6u);
  EXPECT_FALSE(obj.dmg.nodes.empty());
  auto v = run({"validate", dir / "eraser.h5"});
  EXPECT_EQ(v.exit_code, 0) << v.output;
  // A grasp across the eraser's 5 cm width, approaching from above.
  auto g = run({"grasps", dir / "eraser.h5", "--initial", "0,0,0.02,1,0,0,0", "--json"}, false);
  ASSERT_EQ(g.exit_code, 0) << g.output;
  const auto doc = nlohmann::json::parse(g.output);
  ASSERT_GT(doc["grasps"].size(), 1u);
  EXPECT_EQ(doc["grasps"][0]["cost"], 0.0);
  EXPECT_TRUE(doc["grasps"][0]["actions"].empty());
  bool translation = false, rotation = false;
  for (const auto& gr : doc["grasps"])
    for (const auto& a : gr["actions"]) {
      translation |= a["type"] == "translation";
      rotation |= a["type"] == "rotation";
    }
  EXPECT_TRUE(translation);
  EXPECT_TRUE(rotation);
  auto text = run({"grasps", dir / "eraser.h5", "--initial", "0,0,0.02,1,0,0,0"});
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.output.find("reachable grasps"), std::string::npos);
}

TEST(ObjectCli, BadGripperAndOptionsAreRejected) {
  TempDir dir;
  ASSERT_EQ(run({"make-objects", "--out", dir.path()}).exit_code, 0);
  dmgplace::test::write_text(dir / "g.yaml", "max_opening: 0.08\nfinger: {length: -1}\n");
  auto bad = run({"bake-object", dir / "eraser.stl", "--gripper", dir / "g.yaml", "--out", dir / "e.h5"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("finger.length"), std::string::npos) << bad.output;
  auto step = run({"bake-object", dir / "eraser.stl", "--angle-step", "7", "--out", dir / "e.h5"});
  EXPECT_NE(step.exit_code, 0);
  EXPECT_NE(step.output.find("--angle-step"), std::string::npos) << step.output;
  auto pose = run({"grasps", dir / "nope.h5", "--initial", "0,0,0"});
  EXPECT_NE(pose.exit_code, 0);
}

TEST(ObjectCli, BothYcbObjectsBakeAndValidate) {
  DMGPLACE_REQUIRE_SHARED();
  TempDir dir;
  const auto ycb = dmgplace::test::shared_datasets() / "objects/ycb";
  for (const char* name : {"003_cracker_box", "006_mustard_bottle"}) {
    const fs::path out = dir / (std::string(name) + ".h5");
    auto bake = run({"bake-object", ycb / (std::string(name) + "_textured.obj"), "--out", out});
    ASSERT_EQ(bake.exit_code, 0) << name << ": " << bake.output;
    auto v = run({"validate", out});
    EXPECT_EQ(v.exit_code, 0) << v.output;
    const auto obj = dmgplace::formats::load_object(out);
    EXPECT_GE(obj.placement.faces.size(), 2u) << name;
    EXPECT_GT(obj.dmg.nodes.size(), 20u) << name;
    EXPECT_GT(obj.dmg.edges.size(), obj.dmg.nodes.size()) << name;
  }
}

TEST(ObjectCli, TrayOfTheOriginalDmgIsOfTheSameOrder) {
  DMGPLACE_REQUIRE_SHARED();
  TempDir dir;
  const auto ref = dmgplace::test::shared_datasets() / "dmg_reference";
  // DMG_tray.launch: seed 13 mm, angle step 20 deg, normal threshold 0.15; the STL is in mm.
  auto bake = run({"bake-object", ref / "shapes/tray.stl", "--scale", "0.001", "--seed-resolution", "0.013",
                   "--angle-step", "20", "--normal-threshold", "0.15", "--out", dir / "tray.h5"});
  ASSERT_EQ(bake.exit_code, 0) << bake.output;
  EXPECT_EQ(run({"validate", dir / "tray.h5"}).exit_code, 0);
  const auto obj = dmgplace::formats::load_object(dir / "tray.h5");
  // The reference: 84 nodes, all on one facet, 428 directed edges (5.1 per node); see docs/dmg.md.
  std::ifstream graph(ref / "files/graph_tray_13_20.txt");
  std::string line;
  int ref_nodes = 0;
  while (std::getline(graph, line)) ref_nodes += !line.empty();
  ASSERT_EQ(ref_nodes, 84);
  const double nodes = double(obj.dmg.nodes.size());
  EXPECT_GT(nodes, ref_nodes / 4.0);
  EXPECT_LT(nodes, ref_nodes * 10.0);
  const double per_node = obj.dmg.edges.size() / nodes;
  EXPECT_GT(per_node, 5.1 / 4);
  EXPECT_LT(per_node, 5.1 * 4);
  std::set<int> facets;
  for (const auto& n : obj.dmg.nodes) facets.insert(n.facet);
  EXPECT_LE(facets.size(), 2u);  // the two broad faces only: the 5 mm rim is too narrow to grasp across 200 mm
}
