// End-to-end: the dmgplace command on the built-in data, its exit codes and its error messages.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <random>
#include <thread>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "dmgplace/formats/object_artifact.hpp"
#include "full_disk.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using dmgplace::test::TempDir;

namespace {
struct CliRun {
  int code = -1;
  std::string out;  // stdout and stderr together
};

CliRun run(const std::string& args) {
  CliRun r;
  std::string cmd = dmgplace::test::cli_path() + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, p)) r.out.append(buf, n);
  int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
fs::path data() { return dmgplace::test::source_dir() / "datasets"; }
}  // namespace

TEST(Cli, BakesValidatesAndInspectsTheBuiltInObjects) {
  TempDir dir;
  ASSERT_EQ(run("make-objects --out " + q(dir.path())).code, 0);
  CliRun bake = run("bake-object " + q(dir / "eraser.stl") + " --out " + q(dir / "eraser.h5"));
  ASSERT_EQ(bake.code, 0) << bake.out;
  CliRun v = run("validate " + q(dir / "eraser.h5"));
  EXPECT_EQ(v.code, 0) << v.out;
  CliRun j = run("inspect --json " + q(dir / "eraser.h5"));
  ASSERT_EQ(j.code, 0) << j.out;
  auto doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["schema"], "dmgplace.object v2");
  EXPECT_EQ(doc["inputs"].size(), 1u);
  // The eraser is a box: its volume integral is exact and its COM is its centre.
  auto obj = dmgplace::formats::load_object(dir / "eraser.h5");
  Eigen::Vector3d ext = obj.mesh.vertices.colwise().maxCoeff() - obj.mesh.vertices.colwise().minCoeff();
  EXPECT_NEAR(obj.mass.volume, ext.prod(), 1e-12);
  EXPECT_LT((obj.mass.com - 0.5 * (obj.mesh.vertices.colwise().maxCoeff() + obj.mesh.vertices.colwise().minCoeff()).transpose()).norm(), 1e-12);
  // Inertia of a solid box about its centre: m/12 (b^2 + c^2).
  EXPECT_NEAR(obj.mass.inertia(0, 0), obj.mass.mass / 12 * (ext.y() * ext.y() + ext.z() * ext.z()), 1e-12);

  CliRun com = run("bake-object " + q(dir / "bottle.stl") + " --com 0,0,0.05 --mass 0.2 --out " + q(dir / "bottle.h5"));
  ASSERT_EQ(com.code, 0) << com.out;
  auto bottle = dmgplace::formats::load_object(dir / "bottle.h5");
  EXPECT_TRUE(bottle.mass.com_overridden);
  EXPECT_EQ(bottle.mass.com, Eigen::Vector3d(0, 0, 0.05));
  EXPECT_DOUBLE_EQ(bottle.mass.mass, 0.2);
}

TEST(Cli, BakesTheBuiltInRobotAndScenes) {
  TempDir dir;
  CliRun r = run("bake-robot " + q(data() / "robots/dmgarm/dmgarm.urdf") + " --srdf " +
              q(data() / "robots/dmgarm/dmgarm.srdf") + " --arm dmgarm_link0:dmgarm_tcp --out " + q(dir / "arm.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  for (auto scene : {"cabinet", "table"}) {
    std::string volume = dmgplace::test::read_text(data() / "scenes" / (std::string(scene) + ".volume"));
    while (!volume.empty() && std::isspace(static_cast<unsigned char>(volume.back()))) volume.pop_back();
    CliRun e = run("bake-env " + q(data() / "scenes" / (std::string(scene) + ".yaml")) + " --volume " + volume +
                " --out " + q(dir / (std::string(scene) + ".h5")));
    ASSERT_EQ(e.code, 0) << e.out;
  }
  CliRun v = run("validate " + q(dir / "arm.h5") + " " + q(dir / "cabinet.h5") + " " + q(dir / "table.h5"));
  EXPECT_EQ(v.code, 0) << v.out;
}

TEST(Cli, BadInputsFailWithMessagesNamingTheProblem) {
  TempDir dir;
  CliRun missing = run("bake-object " + q(dir / "nope.stl") + " --out " + q(dir / "o.h5"));
  EXPECT_NE(missing.code, 0);
  EXPECT_NE(missing.out.find("nope.stl"), std::string::npos) << missing.out;
  EXPECT_FALSE(fs::exists(dir / "o.h5"));

  CliRun arm = run("bake-robot " + q(data() / "robots/dmgarm/dmgarm.urdf") + " --arm dmgarm_link0:no_such_link --out " +
                q(dir / "r.h5"));
  EXPECT_NE(arm.code, 0);
  EXPECT_NE(arm.out.find("no_such_link"), std::string::npos) << arm.out;

  CliRun vol = run("bake-env " + q(data() / "scenes/table.yaml") + " --volume 1,2,3 --out " + q(dir / "e.h5"));
  EXPECT_NE(vol.code, 0);
  EXPECT_NE(vol.out.find("--volume"), std::string::npos) << vol.out;
  CliRun inverted = run("bake-env " + q(data() / "scenes/table.yaml") + " --volume 1,0,0,0,1,1 --out " + q(dir / "e.h5"));
  EXPECT_NE(inverted.code, 0);
  EXPECT_NE(inverted.out.find("min below its max"), std::string::npos) << inverted.out;

  dmgplace::test::write_text(dir / "junk.h5", "junk");
  CliRun v = run("validate " + q(dir / "junk.h5"));
  EXPECT_EQ(v.code, 1);
  EXPECT_NE(v.out.find("junk.h5"), std::string::npos);
  EXPECT_NE(v.out.find("not an HDF5 file"), std::string::npos);

  CliRun usage = run("bake-object");
  EXPECT_NE(usage.code, 0);
}

TEST(Cli, ValidateFindsACorruptedArtifact) {
  TempDir dir;
  ASSERT_EQ(run("make-objects --out " + q(dir.path())).code, 0);
  ASSERT_EQ(run("bake-object " + q(dir / "bottle.stl") + " --out " + q(dir / "b.h5")).code, 0);
  std::string bytes = dmgplace::test::read_text(dir / "b.h5");
  // Flip bytes in the middle of the file, where the mesh data lives.
  for (std::size_t i = bytes.size() / 2; i < bytes.size() / 2 + 8; ++i) bytes[i] = char(~bytes[i]);
  dmgplace::test::write_text(dir / "b.h5", bytes);
  CliRun v = run("validate " + q(dir / "b.h5"));
  EXPECT_EQ(v.code, 1) << v.out;
  EXPECT_NE(v.out.find("b.h5"), std::string::npos);
}

TEST(Cli, SharedRealDataBakes) {
  DMGPLACE_REQUIRE_SHARED();
  TempDir dir;
  auto shared = dmgplace::test::shared_datasets();
  CliRun panda = run("bake-robot " + q(shared / "panda/moveit_resources_panda_description/urdf/panda.urdf") + " --srdf " +
                  q(shared / "panda/panda_moveit_config/config/panda.srdf") + " --package-path " + q(shared / "panda") +
                  " --arm panda_link0:panda_hand --out " + q(dir / "panda.h5"));
  ASSERT_EQ(panda.code, 0) << panda.out;
  CliRun ycb = run("bake-object " + q(shared / "objects/ycb/006_mustard_bottle_textured.obj") + " --out " + q(dir / "mustard.h5"));
  ASSERT_EQ(ycb.code, 0) << ycb.out;
  CliRun mbm = run("bake-env " + q(shared / "env/motion_bench_maker/configs/scenes/bookshelf/scene_small.yaml") +
                " --volume 0.3,-0.6,0.9,1.6,0.6,1.9 --out " + q(dir / "shelf.h5"));
  ASSERT_EQ(mbm.code, 0) << mbm.out;
  CliRun scan = run("bake-env " + q(shared / "scans/pcl/table_scene_mug_stereo_textured.pcd") +
                 " --volume -1,-1,-1,1,1,2 --frame 0,0,0,0,0,0 --out " + q(dir / "scan.h5"));
  ASSERT_EQ(scan.code, 0) << scan.out;
  CliRun kitchen = run("bake-env " + q(shared / "env/motion_bench_maker/configs/scenes/kitchen/kitchen.urdf") +
                    " --volume -2,-2,0,2,2,2 --out " + q(dir / "kitchen.h5"));
  ASSERT_EQ(kitchen.code, 0) << kitchen.out;
  CliRun v = run("validate " + q(dir / "panda.h5") + " " + q(dir / "mustard.h5") + " " + q(dir / "shelf.h5") + " " +
              q(dir / "scan.h5") + " " + q(dir / "kitchen.h5"));
  EXPECT_EQ(v.code, 0) << v.out;
}

// kill -9 at random moments of a bake: the previous artifact stays intact and valid, and the only
// leftovers are hidden temporary files, which the next bake of the same target removes.
TEST(Cli, KilledBakesLeaveThePreviousArtifactIntact) {
  TempDir dir;
  const std::string volume = "0.55,-0.40,0.45,0.88,0.40,1.05";
  const std::string args = "bake-env " + q(data() / "scenes/cabinet.yaml") + " --volume " + volume +
                           " --resolution 0.004 --out " + q(dir / "env.h5");
  ASSERT_EQ(run(args).code, 0);
  const std::string before = dmgplace::test::read_text(dir / "env.h5");
  std::mt19937 rng(99);
  int killed = 0;
  for (int i = 0; i < 20; ++i) {
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      std::string cmd = dmgplace::test::cli_path() + " " + args + " >/dev/null 2>&1";
      execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20 + rng() % 400));
    killed += ::kill(pid, SIGKILL) == 0;
    int status = 0;
    waitpid(pid, &status, 0);
    // Either the bake finished (a new, complete artifact) or it died: never a partial file.
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      EXPECT_EQ(run("validate " + q(dir / "env.h5")).code, 0);
    } else {
      const std::string now = dmgplace::test::read_text(dir / "env.h5");
      if (now != before) {
        EXPECT_EQ(run("validate " + q(dir / "env.h5")).code, 0);
      }
    }
    for (auto& e : fs::directory_iterator(dir.path())) {
      const std::string name = e.path().filename().string();
      EXPECT_TRUE(name == "env.h5" || (name.rfind(".env.h5.tmp.", 0) == 0)) << "unexpected file " << name;
    }
  }
  EXPECT_GT(killed, 10);
  ASSERT_EQ(run(args).code, 0);
  std::size_t files = 0;
  for (auto& e : fs::directory_iterator(dir.path())) files += e.is_regular_file();
  EXPECT_EQ(files, 1u) << "a completed bake removes the temporary files of killed ones";
}

// A bake onto a full disk: a clear error naming the artifact, a non-zero exit (not a crash), and
// neither a partial artifact nor a temporary file left to fill the disk further. The bottle's
// artifact is 36 KB: the disk runs out at its creation, in its datasets and at its metadata.
TEST(Cli, BakeOntoAFullDiskFailsCleanly) {
  TempDir in;
  ASSERT_EQ(run("make-objects --out " + q(in.path())).code, 0);
  for (const char* size : {"64k", "4k", "16k", "24k", "32k"}) {
    SCOPED_TRACE(std::string("tmpfs of ") + size);
    dmgplace::test::SmallDisk disk(size);
    if (!disk.mounted()) GTEST_SKIP() << disk.why_not() << "; Cli.BakeOverTheFileSizeLimitFailsCleanly covers the same";
    if (std::string(size) == "64k") disk.fill();  // full before the bake starts
    CliRun bake = run("bake-object " + q(in / "bottle.stl") + " --out " + q(disk / "bottle.h5"));
    EXPECT_EQ(bake.code, 1) << bake.out;
    EXPECT_NE(bake.out.find("error: " + (disk / "bottle.h5").string()), std::string::npos) << bake.out;
    EXPECT_NE(bake.out.find("disk full"), std::string::npos) << bake.out;
    EXPECT_TRUE(disk.files_except().empty()) << "left: " << ::testing::PrintToString(disk.files_except());
  }
}

// The same without root: the bake's files may not grow past a limit (RLIMIT_FSIZE).
TEST(Cli, BakeOverTheFileSizeLimitFailsCleanly) {
  TempDir in, out;
  ASSERT_EQ(run("make-objects --out " + q(in.path())).code, 0);
  for (rlim_t limit : {0, 4096, 16384, 32768}) {
    SCOPED_TRACE("limit " + std::to_string(limit));
    const auto bake = dmgplace::test::cli_with_file_size_limit(
        limit, "bake-object " + q(in / "bottle.stl") + " --out " + q(out / "bottle.h5"));
    EXPECT_EQ(bake.code, 1) << bake.message;
    EXPECT_NE(bake.message.find("error: " + (out / "bottle.h5").string()), std::string::npos) << bake.message;
    EXPECT_NE(bake.message.find("disk full"), std::string::npos) << bake.message;
    EXPECT_TRUE(fs::is_empty(out.path()));
  }
}
