// `dmgplace validate --set` and `--check-inputs`: artifacts that are each sound but do not belong
// together are refused naming both files; an input changed since the bake is reported.
#include <gtest/gtest.h>

#include "placement_fixture.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {
class ArtifactSet : public test::PlacementFixture {};
}  // namespace

TEST_F(ArtifactSet, TheBuiltInSetFitsInAnyOrder) {
  const fs::path d = dir_->path();
  const auto r = test::run_cli({"validate", "--set", d / "cabinet.h5", d / "arm.h5", d / "bottle.h5"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("set: ok"), std::string::npos) << r.output;
  const auto j = test::run_cli({"validate", "--set", "--json", d / "arm.h5", d / "bottle.h5", d / "cabinet.h5"});
  EXPECT_EQ(j.exit_code, 0) << j.output;
  EXPECT_NE(j.output.find("\"set\": {"), std::string::npos) << j.output;
}

TEST_F(ArtifactSet, AnObjectBakedForAWiderGripperIsRefusedNamingBothFiles) {
  const fs::path d = dir_->path();
  std::string gripper = test::read_text(test::source_dir() / "datasets/grippers/dmgarm_hand.yaml");
  const auto at = gripper.find("max_opening: 0.08");
  ASSERT_NE(at, std::string::npos);
  gripper.replace(at, 17, "max_opening: 0.20");
  test::write_text(d / "wide_hand.yaml", gripper);
  ASSERT_EQ(test::run_cli({"bake-object", d / "bottle.stl", "--mass", "0.15", "--gripper", d / "wide_hand.yaml",
                           "--out", d / "bottle_wide.h5"})
                .exit_code,
            0);
  const auto r = test::run_cli({"validate", "--set", d / "arm.h5", d / "bottle_wide.h5", d / "cabinet.h5"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bottle_wide.h5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("arm.h5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("opening 0.2 m"), std::string::npos) << r.output;
  // The query loader refuses the same set.
  test::write_text(d / "wide.yaml",
                   "robot: arm.h5\nobject: bottle_wide.h5\nenvironment: cabinet.h5\n"
                   "start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]\n"
                   "initial_grasp: {pose: [0, 0, 0.06, 0, 0.7071068, 0, 0.7071068]}\n");
  const auto place = test::run_cli({"place", d / "wide.yaml", "--time-limit", "1", "--out", d / "wide_out"});
  EXPECT_EQ(place.exit_code, 1) << place.output;
  EXPECT_NE(place.output.find("opening"), std::string::npos) << place.output;
}

TEST_F(ArtifactSet, ASceneOutOfReachAndBadSetsAreRefused) {
  const fs::path d = dir_->path();
  const fs::path data = test::source_dir() / "datasets";
  const std::string volume = test::builtin_volume("cabinet");
  // The scene placed 4 m away (as a wrong --frame would): the volume moves with it.
  std::string far_volume;
  {
    std::vector<double> v;
    std::stringstream in(volume);
    for (std::string x; std::getline(in, x, ',');) v.push_back(std::stod(x));
    ASSERT_EQ(v.size(), 6u);
    v[0] += 4, v[3] += 4;
    for (std::size_t i = 0; i < 6; ++i) far_volume += (i ? "," : "") + std::to_string(v[i]);
  }
  ASSERT_EQ(test::run_cli({"bake-env", data / "scenes/cabinet.yaml", "--volume", far_volume, "--frame", "4,0,0,0,0,0",
                           "--out", d / "far.h5"})
                .exit_code,
            0);
  const auto far = test::run_cli({"validate", "--set", d / "arm.h5", d / "bottle.h5", d / "far.h5"});
  EXPECT_EQ(far.exit_code, 1) << far.output;
  EXPECT_NE(far.output.find("far.h5"), std::string::npos) << far.output;
  EXPECT_NE(far.output.find("reach"), std::string::npos) << far.output;
  // Two environments and no object; the wrong number of files.
  const auto two = test::run_cli({"validate", "--set", d / "arm.h5", d / "cabinet.h5", d / "far.h5"});
  EXPECT_EQ(two.exit_code, 1);
  EXPECT_NE(two.output.find("no dmgplace.object"), std::string::npos) << two.output;
  const auto count = test::run_cli({"validate", "--set", d / "arm.h5", d / "bottle.h5"});
  EXPECT_EQ(count.exit_code, 1);
  EXPECT_NE(count.output.find("three artifacts"), std::string::npos) << count.output;
}

TEST_F(ArtifactSet, AnInputChangedSinceTheBakeIsReported) {
  const fs::path d = dir_->path();
  fs::copy_file(d / "bottle.stl", d / "mine.stl", fs::copy_options::overwrite_existing);
  ASSERT_EQ(test::run_cli({"bake-object", d / "mine.stl", "--mass", "0.15", "--out", d / "mine.h5"}).exit_code, 0);
  const auto fresh = test::run_cli({"validate", "--check-inputs", d / "mine.h5"});
  EXPECT_EQ(fresh.exit_code, 0) << fresh.output;
  // One byte of the STL header (not geometry) changes the file's hash.
  std::string bytes = test::read_text(d / "mine.stl");
  bytes[0] = bytes[0] == 'x' ? 'y' : 'x';
  test::write_text(d / "mine.stl", bytes);
  const auto stale = test::run_cli({"validate", "--check-inputs", d / "mine.h5"});
  EXPECT_EQ(stale.exit_code, 1) << stale.output;
  EXPECT_NE(stale.output.find("mine.stl"), std::string::npos) << stale.output;
  EXPECT_NE(stale.output.find("changed since the bake"), std::string::npos) << stale.output;
  // Without the flag the artifact is still sound on its own.
  EXPECT_EQ(test::run_cli({"validate", d / "mine.h5"}).exit_code, 0);
}

TEST_F(ArtifactSet, MeshesASceneNamesAreInputsToo) {
  // A scene file naming a mesh: the environment's header lists the mesh with its hash, so a
  // changed mesh makes the artifact stale though the scene file did not change.
  const fs::path d = dir_->path() / "provenance";
  fs::create_directories(d);
  fs::copy_file(dir_->path() / "bottle.stl", d / "thing.stl", fs::copy_options::overwrite_existing);
  test::write_text(d / "scene.yaml",
                   "world:\n  collision_objects:\n"
                   "    - {id: floor, primitives: [{type: box, dimensions: [2, 2, 0.02]}],\n"
                   "       primitive_poses: [{position: [0.5, 0, -0.01], orientation: [0, 0, 0, 1]}]}\n"
                   "    - {id: thing, meshes: [{resource: thing.stl}],\n"
                   "       mesh_poses: [{position: [0.6, 0, 0], orientation: [0, 0, 0, 1]}]}\n");
  const auto bake = test::run_cli(
      {"bake-env", d / "scene.yaml", "--volume", "0.3,-0.3,0,0.9,0.3,0.4", "--out", d / "env.h5", "--json"});
  ASSERT_EQ(bake.exit_code, 0) << bake.output;
  EXPECT_NE(bake.output.find("thing.stl"), std::string::npos) << "the mesh is an input: " << bake.output;
  EXPECT_EQ(test::run_cli({"validate", "--check-inputs", d / "env.h5"}).exit_code, 0);
  std::string bytes = test::read_text(d / "thing.stl");
  bytes[0] = bytes[0] == 'x' ? 'y' : 'x';
  test::write_text(d / "thing.stl", bytes);
  const auto stale = test::run_cli({"validate", "--check-inputs", d / "env.h5"});
  EXPECT_EQ(stale.exit_code, 1) << stale.output;
  EXPECT_NE(stale.output.find("thing.stl"), std::string::npos) << stale.output;
}
