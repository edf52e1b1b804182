// MANIFEST.yaml of `dmgplace batch`: the product form and the explicit list of runs, identities
// that follow file contents (not paths), and mistakes named with their element.
#include "dmgplace/tools/batch/batch_manifest.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>

#include "dmgplace/tools/batch/batch_plan.hpp"
#include "dmgplace/tools/geometry/procedural_meshes.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

struct Files {
  test::TempDir dir;
  Files() {
    write_stl_binary(make_eraser_mesh(), dir / "eraser.stl");
    write_stl_binary(make_bottle_mesh(), dir / "bottle.stl");
    write_stl_binary(make_eraser_mesh(), dir / "eraser_copy.stl");  // the same bytes under another name
  }
  fs::path manifest(const std::string& queries) {
    const fs::path data = test::source_dir() / "datasets";
    test::write_text(dir / "m.yaml", "robots:\n  arm: {urdf: " + (data / "robots/dmgarm/dmgarm.urdf").string() +
                                         ", arm: \"dmgarm_link0:dmgarm_tcp\"}\n"
                                         "objects:\n  eraser: {mesh: eraser.stl}\n  bottle: {mesh: bottle.stl}\n"
                                         "  copy: {mesh: eraser_copy.stl}\n"
                                         "environments:\n  table: {scene: " +
                                         (data / "scenes/table.yaml").string() +
                                         ", volume: [0.3, -0.3, 0.4, 0.8, 0.3, 0.7]}\n" + queries);
    return dir / "m.yaml";
  }
};

const std::string kTemplate =
    "queries:\n  - name: q\n    robot: arm\n    initial_grasps: {top: [0, 0, 0.0175, 1, 0, 0, 0], side: [0, 0, 0.01, "
    "0, 0.7071068, 0, 0.7071068]}\n"
    "    start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]\n";

TEST(BatchManifest, TheProductAndTheExplicitListPlanTheirRuns) {
  Files f;
  auto plan =
      plan_batch(read_batch_manifest(f.manifest(kTemplate + "    objects: [eraser, bottle]\n    environments: [table]\n"
                                                            "    variants: [full, no-regrasp]\n    seeds: 3\n")),
                 f.dir / "out");
  std::size_t queries = 0;
  for (const auto& t : plan.tasks) queries += t.kind == "query";
  EXPECT_EQ(queries, 2u * 1 * 2 * 2 * 3);  // objects x environments x grasps x variants x seeds
  plan = plan_batch(
      read_batch_manifest(f.manifest(
          kTemplate +
          "    runs:\n      - {object: bottle, environment: table, grasp: side, variant: random-grasp, seed: 7}\n"
          "      - {object: eraser, environment: table, grasp: top}\n")),
      f.dir / "out");
  std::vector<const BatchTask*> q;
  for (const auto& t : plan.tasks)
    if (t.kind == "query") q.push_back(&t);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0]->object, "bottle");
  EXPECT_EQ(q[0]->variant, "random-grasp");
  EXPECT_EQ(q[0]->seed, 7);
  EXPECT_THAT(q[0]->query_yaml, HasSubstr("seed: 7\nvariant: random-grasp"));
  EXPECT_EQ(q[1]->variant, "full");
  // Every identity differs, and files with the same bytes bake to the same identity.
  std::set<std::string> ids;
  std::string eraser, copy;
  for (const auto& t : plan.tasks) {
    ids.insert(t.id);
    if (t.name == "object eraser") eraser = t.id;
    if (t.name == "object copy") copy = t.id;
  }
  EXPECT_EQ(eraser, copy);
  EXPECT_EQ(ids.size(), plan.tasks.size() - 1);
}

TEST(BatchManifest, MistakesNameTheirElement) {
  Files f;
  const auto error = [&](const std::string& queries) {
    return test::error_of([&] { read_batch_manifest(f.manifest(queries)); });
  };
  EXPECT_THAT(error(kTemplate + "    runs: [{object: bottle, environment: table, grasp: front}]\n"),
              HasSubstr("queries[0].runs[0].grasp: no grasp 'front'"));
  EXPECT_THAT(error(kTemplate + "    runs: [{object: mug, environment: table, grasp: top}]\n"),
              HasSubstr("no object 'mug'"));
  EXPECT_THAT(error(kTemplate + "    objects: [eraser]\n    environments: [table]\n    runs: [{object: eraser, "
                                "environment: table, grasp: top}]\n"),
              HasSubstr("not both"));
  EXPECT_THAT(error(kTemplate + "    objects: [eraser]\n    environments: [kitchen]\n"),
              HasSubstr("no environment 'kitchen'"));
  EXPECT_THAT(error(kTemplate + "    objects: [eraser]\n    environments: [table]\n    sedes: 3\n"),
              HasSubstr("sedes"));
  EXPECT_THAT(error(kTemplate + "    objects: [eraser]\n    environments: [table]\n    variants: [best]\n"),
              HasSubstr("unknown variant 'best'"));
}

}  // namespace
}  // namespace dmgplace::tools
