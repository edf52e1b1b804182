// End-to-end: the dmgplace command on the built-in data, its exit codes and its error messages.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <random>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "dmgplace/formats/object_artifact.hpp"
#include "full_disk.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using dmgplace::test::TempDir;

namespace {
using CliRun = dmgplace::test::ProcessResult;  // output: stdout and stderr together
using Args = std::vector<dmgplace::test::Arg>;

CliRun run(const Args& args) { return dmgplace::test::run_cli(args); }

fs::path data() { return dmgplace::test::source_dir() / "datasets"; }
}  // namespace

TEST(Cli, BakesValidatesAndInspectsTheBuiltInObjects) {
  TempDir dir;
  ASSERT_EQ(run({"make-objects", "--out", dir.path()}).exit_code, 0);
  CliRun bake = run({"bake-object", dir / "eraser.stl", "--out", dir / "eraser.h5"});
  ASSERT_EQ(bake.exit_code, 0) << bake.output;
  CliRun v = run({"validate", dir / "eraser.h5"});
  EXPECT_EQ(v.exit_code, 0) << v.output;
  CliRun j = run({"inspect", "--json", dir / "eraser.h5"});
  ASSERT_EQ(j.exit_code, 0) << j.output;
  auto doc = nlohmann::json::parse(j.output);
  EXPECT_EQ(doc["schema"], std::string("dmgplace.object v") + std::to_string(dmgplace::formats::kObjectSchemaVersion));
  ASSERT_EQ(doc["inputs"].size(), 1u);
  EXPECT_EQ(doc["inputs"][0]["sha256"].get<std::string>().size(), 64u);
  // Typed JSON: counts are numbers, bounds arrays of numbers.
  EXPECT_TRUE(doc["vertices"].is_number_integer()) << doc["vertices"];
  EXPECT_EQ(doc["triangles"].get<int>(), 12);
  ASSERT_TRUE(doc["bounds_min"].is_array());
  EXPECT_NEAR(doc["bounds_min"][0].get<double>(), -0.065, 1e-6);
  EXPECT_TRUE(doc["mass_kg"].is_number());
  // The eraser is a box: its volume integral is exact and its COM is its center.
  auto obj = dmgplace::formats::load_object(dir / "eraser.h5");
  Eigen::Vector3d ext = obj.mesh.vertices.colwise().maxCoeff() - obj.mesh.vertices.colwise().minCoeff();
  EXPECT_NEAR(obj.mass.volume, ext.prod(), 1e-12);
  EXPECT_LT((obj.mass.com -
             0.5 * (obj.mesh.vertices.colwise().maxCoeff() + obj.mesh.vertices.colwise().minCoeff()).transpose())
                .norm(),
            1e-12);
  // Inertia of a solid box about its center: m/12 (b^2 + c^2).
  EXPECT_NEAR(obj.mass.inertia(0, 0), obj.mass.mass / 12 * (ext.y() * ext.y() + ext.z() * ext.z()), 1e-12);

  CliRun com = run(
      {"bake-object", dir / "bottle.stl", "--com", "0,0,0.05", "--mass", "0.2", "--out", dir / "bottle.h5", "--json"});
  ASSERT_EQ(com.exit_code, 0) << com.output;
  // --json on a bake: what was written, how long it took, and the artifact's typed summary.
  const auto baked = nlohmann::json::parse(com.output);
  EXPECT_EQ(baked["written"].get<std::string>(), (dir / "bottle.h5").string());
  EXPECT_GT(baked["seconds"].get<double>(), 0.0);
  EXPECT_TRUE(baked["artifact"]["dmg_nodes"].is_number_integer()) << baked["artifact"];
  EXPECT_DOUBLE_EQ(baked["artifact"]["parameters"]["mass"].get<double>(), 0.2);
  auto bottle = dmgplace::formats::load_object(dir / "bottle.h5");
  EXPECT_TRUE(bottle.mass.com_overridden);
  EXPECT_EQ(bottle.mass.com, Eigen::Vector3d(0, 0, 0.05));
  EXPECT_DOUBLE_EQ(bottle.mass.mass, 0.2);
}

// Issue 22: one table per bake binds each option and writes the header, so every numeric option
// shows its default, range and (where it has one) unit, and the header records what ran.
TEST(Cli, EveryBakeOptionShowsItsDefaultAndTheHeaderRecordsIt) {
  for (const char* cmd : {"bake-object", "bake-env", "bake-robot"}) {
    const CliRun help = run({cmd, "--help"});
    ASSERT_EQ(help.exit_code, 0) << help.output;
    std::istringstream lines(help.output);
    int numeric = 0;
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("  --", 0) == 0 &&
          (line.find(" FLOAT") != std::string::npos || line.find(" INT") != std::string::npos)) {
        ++numeric;
        EXPECT_NE(line.find(" in ["), std::string::npos) << cmd << ": no range: " << line;
        EXPECT_NE(line.find("]="), std::string::npos) << cmd << ": no default: " << line;
      }
    EXPECT_GE(numeric, 5) << cmd;
  }
  TempDir dir;
  ASSERT_EQ(run({"make-objects", "--out", dir.path()}).exit_code, 0);
  ASSERT_EQ(run({"bake-object", dir / "eraser.stl", "--angle-step", "20", "--out", dir / "e.h5"}).exit_code, 0);
  const auto params = nlohmann::json::parse(dmgplace::formats::load_object(dir / "e.h5").header.parameters_json);
  EXPECT_DOUBLE_EQ(params["angle_step"].get<double>(), 20);         // given
  EXPECT_DOUBLE_EQ(params["seed_resolution"].get<double>(), 0.01);  // default, still recorded
  EXPECT_DOUBLE_EQ(params["rotation_weight"].get<double>(), 0.1);
  EXPECT_EQ(params["reconstruct"], "poisson");
}

// Issue 22: every command takes --log-level, -v and -q; -q keeps warnings and errors only.
TEST(Cli, LogLevelsGovernWhatGoesToStderr) {
  TempDir dir;
  const auto urdf = data() / "robots/dmgarm/dmgarm.urdf";
  // Without an SRDF the bake says (info) what it decided about the link pairs.
  const auto chatty =
      dmgplace::test::run_cli({"bake-robot", urdf, "--arm", "dmgarm_link0:dmgarm_tcp", "--out", dir / "a.h5"});
  ASSERT_EQ(chatty.exit_code, 0) << chatty.output;
  EXPECT_NE(chatty.output.find("no --srdf:"), std::string::npos) << chatty.output;
  for (const std::vector<dmgplace::test::Arg>& quiet : {std::vector<dmgplace::test::Arg>{"-q", "bake-robot"},
                                                        {"bake-robot", "-q"},
                                                        {"--log-level", "error", "bake-robot"}}) {
    std::vector<dmgplace::test::Arg> args = quiet;
    for (const dmgplace::test::Arg& a :
         {dmgplace::test::Arg(urdf), dmgplace::test::Arg("--arm"), dmgplace::test::Arg("dmgarm_link0:dmgarm_tcp"),
          dmgplace::test::Arg("--out"), dmgplace::test::Arg(dir / "b.h5")})
      args.push_back(a);
    const auto r = dmgplace::test::run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("no --srdf:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("wrote"), std::string::npos) << "results stay on stdout: " << r.output;
  }
  // Errors still show under -q; an unknown level is a usage error.
  const auto missing = run({"-q", "validate", dir / "none.h5"});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("none.h5"), std::string::npos) << missing.output;
  const auto bad = run({"--log-level", "chatty", "validate", dir / "a.h5"});
  EXPECT_GE(bad.exit_code, 100) << bad.output;
  EXPECT_EQ(run({"-v", "validate", dir / "a.h5"}).exit_code, 0);
}

TEST(Cli, BakesTheBuiltInRobotAndScenes) {
  TempDir dir;
  CliRun r = run({"bake-robot", data() / "robots/dmgarm/dmgarm.urdf", "--srdf", data() / "robots/dmgarm/dmgarm.srdf",
                  "--arm", "dmgarm_link0:dmgarm_tcp", "--out", dir / "arm.h5"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (auto scene : {"cabinet", "table"}) {
    const std::string volume = dmgplace::test::builtin_volume(scene);
    CliRun e = run({"bake-env", data() / "scenes" / (std::string(scene) + ".yaml"), "--volume", volume, "--out",
                    dir / (std::string(scene) + ".h5"), "--json"});
    ASSERT_EQ(e.exit_code, 0) << e.output;
    // The header records the option as given (0 asks for V's diagonal) and the band that was used.
    const auto baked = nlohmann::json::parse(e.output);
    EXPECT_EQ(baked["artifact"]["parameters"]["clearance_band"].get<double>(), 0.0) << e.output;
    EXPECT_GT(baked["artifact"]["parameters"]["clearance_band_used"].get<double>(), 0.5) << e.output;
  }
  CliRun v = run({"validate", dir / "arm.h5", dir / "cabinet.h5", dir / "table.h5"});
  EXPECT_EQ(v.exit_code, 0) << v.output;

  // Without an SRDF the allowed pairs are computed, reported, and written for review; passed back
  // with --srdf they bake again.
  CliRun no_srdf =
      run({"bake-robot", data() / "robots/dmgarm/dmgarm.urdf", "--arm", "dmgarm_link0:dmgarm_tcp",
           "--collision-samples", "300", "--write-srdf", dir / "review.srdf", "--out", dir / "arm_no_srdf.h5"});
  ASSERT_EQ(no_srdf.exit_code, 0) << no_srdf.output;
  EXPECT_NE(no_srdf.output.find("no --srdf:"), std::string::npos) << no_srdf.output;
  EXPECT_NE(no_srdf.output.find("adjacent"), std::string::npos) << no_srdf.output;
  EXPECT_NE(dmgplace::test::read_text(dir / "review.srdf").find("reason=\"Adjacent\""), std::string::npos);
  CliRun back = run({"bake-robot", data() / "robots/dmgarm/dmgarm.urdf", "--srdf", dir / "review.srdf", "--arm",
                     "dmgarm_link0:dmgarm_tcp", "--out", dir / "arm_reviewed.h5"});
  EXPECT_EQ(back.exit_code, 0) << back.output;
  EXPECT_EQ(back.output.find("no --srdf:"), std::string::npos) << back.output;
  // --write-srdf with --srdf would write nothing it computed.
  CliRun both = run({"bake-robot", data() / "robots/dmgarm/dmgarm.urdf", "--srdf", dir / "review.srdf", "--write-srdf",
                     dir / "x.srdf", "--arm", "dmgarm_link0:dmgarm_tcp", "--out", dir / "x.h5"});
  EXPECT_EQ(both.exit_code, 1) << both.output;
}

TEST(Cli, BadInputsFailWithMessagesNamingTheProblem) {
  TempDir dir;
  CliRun missing = run({"bake-object", dir / "nope.stl", "--out", dir / "o.h5"});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("nope.stl"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(dir / "o.h5"));

  CliRun arm = run({"bake-robot", data() / "robots/dmgarm/dmgarm.urdf", "--arm", "dmgarm_link0:no_such_link", "--out",
                    dir / "r.h5"});
  EXPECT_NE(arm.exit_code, 0);
  EXPECT_NE(arm.output.find("no_such_link"), std::string::npos) << arm.output;

  CliRun vol = run({"bake-env", data() / "scenes/table.yaml", "--volume", "1,2,3", "--out", dir / "e.h5"});
  EXPECT_NE(vol.exit_code, 0);
  EXPECT_NE(vol.output.find("--volume"), std::string::npos) << vol.output;
  CliRun inverted = run({"bake-env", data() / "scenes/table.yaml", "--volume", "1,0,0,0,1,1", "--out", dir / "e.h5"});
  EXPECT_NE(inverted.exit_code, 0);
  EXPECT_NE(inverted.output.find("min below its max"), std::string::npos) << inverted.output;

  dmgplace::test::write_text(dir / "junk.h5", "junk");
  CliRun v = run({"validate", dir / "junk.h5"});
  EXPECT_EQ(v.exit_code, 1);
  EXPECT_NE(v.output.find("junk.h5"), std::string::npos);
  EXPECT_NE(v.output.find("not an HDF5 file"), std::string::npos);

  CliRun usage = run({"bake-object"});
  EXPECT_NE(usage.exit_code, 0);
}

TEST(Cli, ValidateFindsACorruptedArtifact) {
  TempDir dir;
  ASSERT_EQ(run({"make-objects", "--out", dir.path()}).exit_code, 0);
  ASSERT_EQ(run({"bake-object", dir / "bottle.stl", "--out", dir / "b.h5"}).exit_code, 0);
  std::string bytes = dmgplace::test::read_text(dir / "b.h5");
  // Flip bytes in the middle of the file, where the mesh data lives.
  for (std::size_t i = bytes.size() / 2; i < bytes.size() / 2 + 8; ++i) bytes[i] = char(~bytes[i]);
  dmgplace::test::write_text(dir / "b.h5", bytes);
  CliRun v = run({"validate", dir / "b.h5"});
  EXPECT_EQ(v.exit_code, 1) << v.output;
  EXPECT_NE(v.output.find("b.h5"), std::string::npos);
  // --json: one entry per file, typed, and the same exit status.
  ASSERT_EQ(run({"bake-object", dir / "eraser.stl", "--out", dir / "e.h5"}).exit_code, 0);
  CliRun j = run({"validate", "--json", dir / "b.h5", dir / "e.h5"});
  EXPECT_EQ(j.exit_code, 1) << j.output;
  const auto doc = nlohmann::json::parse(j.output);
  ASSERT_EQ(doc["files"].size(), 2u);
  EXPECT_FALSE(doc["files"][0]["ok"].get<bool>());
  EXPECT_FALSE(doc["files"][0]["problems"].empty());
  EXPECT_TRUE(doc["files"][1]["ok"].get<bool>());
  EXPECT_EQ(doc["bad"].get<int>(), 1);
}

TEST(Cli, SharedRealDataBakes) {
  DMGPLACE_REQUIRE_SHARED();
  TempDir dir;
  auto shared = dmgplace::test::shared_datasets();
  CliRun panda = run({"bake-robot", shared / "panda/moveit_resources_panda_description/urdf/panda.urdf", "--srdf",
                      shared / "panda/panda_moveit_config/config/panda.srdf", "--package-path", shared / "panda",
                      "--arm", "panda_link0:panda_hand", "--out", dir / "panda.h5"});
  ASSERT_EQ(panda.exit_code, 0) << panda.output;
  CliRun ycb =
      run({"bake-object", shared / "objects/ycb/006_mustard_bottle_textured.obj", "--out", dir / "mustard.h5"});
  ASSERT_EQ(ycb.exit_code, 0) << ycb.output;
  CliRun mbm = run({"bake-env", shared / "env/motion_bench_maker/configs/scenes/bookshelf/scene_small.yaml", "--volume",
                    "0.3,-0.6,0.9,1.6,0.6,1.9", "--out", dir / "shelf.h5"});
  ASSERT_EQ(mbm.exit_code, 0) << mbm.output;
  CliRun scan = run({"bake-env", shared / "scans/pcl/table_scene_mug_stereo_textured.pcd", "--volume", "-1,-1,-1,1,1,2",
                     "--frame", "0,0,0,0,0,0", "--out", dir / "scan.h5"});
  ASSERT_EQ(scan.exit_code, 0) << scan.output;
  CliRun kitchen = run({"bake-env", shared / "env/motion_bench_maker/configs/scenes/kitchen/kitchen.urdf", "--volume",
                        "-2,-2,0,2,2,2", "--out", dir / "kitchen.h5"});
  ASSERT_EQ(kitchen.exit_code, 0) << kitchen.output;
  CliRun v =
      run({"validate", dir / "panda.h5", dir / "mustard.h5", dir / "shelf.h5", dir / "scan.h5", dir / "kitchen.h5"});
  EXPECT_EQ(v.exit_code, 0) << v.output;
}

// kill -9 at random moments of a bake: the previous artifact stays intact and valid, and the only
// leftovers are hidden temporary files, which the next bake of the same target removes.
TEST(Cli, KilledBakesLeaveThePreviousArtifactIntact) {
  TempDir dir;
  const std::string volume = "0.55,-0.40,0.45,0.88,0.40,1.05";
  const Args args = {
      "bake-env", data() / "scenes/cabinet.yaml", "--volume", volume, "--resolution", "0.004", "--out", dir / "env.h5"};
  ASSERT_EQ(run(args).exit_code, 0);
  // The child's argument vector, made before fork (the child only calls async-signal-safe functions).
  std::vector<std::string> argv{dmgplace::test::cli_path()};
  for (const auto& a : args) argv.push_back(a.text);
  std::vector<char*> c_argv;
  for (auto& a : argv) c_argv.push_back(a.data());
  c_argv.push_back(nullptr);
  const std::string before = dmgplace::test::read_text(dir / "env.h5");
  std::mt19937 rng(99);
  int killed = 0;
  for (int i = 0; i < 20; ++i) {
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      // The bake itself, not a shell around it, is what gets killed; its output goes nowhere.
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, STDOUT_FILENO);
      ::dup2(null, STDERR_FILENO);
      execv(c_argv[0], c_argv.data());
      _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20 + rng() % 400));
    killed += ::kill(pid, SIGKILL) == 0;
    int status = 0;
    waitpid(pid, &status, 0);
    // Either the bake finished (a new, complete artifact) or it died: never a partial file.
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      EXPECT_EQ(run({"validate", dir / "env.h5"}).exit_code, 0);
    } else {
      const std::string now = dmgplace::test::read_text(dir / "env.h5");
      if (now != before) {
        EXPECT_EQ(run({"validate", dir / "env.h5"}).exit_code, 0);
      }
    }
    for (auto& e : fs::directory_iterator(dir.path())) {
      const std::string name = e.path().filename().string();
      EXPECT_TRUE(name == "env.h5" || (name.rfind(".env.h5.tmp.", 0) == 0)) << "unexpected file " << name;
    }
  }
  EXPECT_GT(killed, 10);
  ASSERT_EQ(run(args).exit_code, 0);
  std::size_t files = 0;
  for (auto& e : fs::directory_iterator(dir.path())) files += e.is_regular_file();
  EXPECT_EQ(files, 1u) << "a completed bake removes the temporary files of killed ones";
}

// A bake onto a full disk: a clear error naming the artifact, a non-zero exit (not a crash), and
// neither a partial artifact nor a temporary file left to fill the disk further. The bottle's
// artifact is 36 KB: the disk runs out at its creation, in its datasets and at its metadata.
TEST(Cli, BakeOntoAFullDiskFailsCleanly) {
  TempDir in;
  ASSERT_EQ(run({"make-objects", "--out", in.path()}).exit_code, 0);
  for (const char* size : {"64k", "4k", "16k", "24k", "32k"}) {
    SCOPED_TRACE(std::string("tmpfs of ") + size);
    dmgplace::test::SmallDisk disk(size);
    if (!disk.mounted()) GTEST_SKIP() << disk.why_not() << "; Cli.BakeOverTheFileSizeLimitFailsCleanly covers the same";
    if (std::string(size) == "64k") disk.fill();  // full before the bake starts
    CliRun bake = run({"bake-object", in / "bottle.stl", "--out", disk / "bottle.h5"});
    EXPECT_EQ(bake.exit_code, 1) << bake.output;
    EXPECT_NE(bake.output.find("error: " + (disk / "bottle.h5").string()), std::string::npos) << bake.output;
    EXPECT_NE(bake.output.find("disk full"), std::string::npos) << bake.output;
    EXPECT_TRUE(disk.files_except().empty()) << "left: " << ::testing::PrintToString(disk.files_except());
  }
}

// The same without root: the bake's files may not grow past a limit (RLIMIT_FSIZE).
TEST(Cli, BakeOverTheFileSizeLimitFailsCleanly) {
  TempDir in, out;
  ASSERT_EQ(run({"make-objects", "--out", in.path()}).exit_code, 0);
  for (rlim_t limit : {0, 4096, 16384, 32768}) {
    SCOPED_TRACE("limit " + std::to_string(limit));
    const auto bake = dmgplace::test::cli_with_file_size_limit(
        limit, {"bake-object", (in / "bottle.stl").string(), "--out", (out / "bottle.h5").string()});
    EXPECT_EQ(bake.code, 1) << bake.message;
    EXPECT_NE(bake.message.find("error: " + (out / "bottle.h5").string()), std::string::npos) << bake.message;
    EXPECT_NE(bake.message.find("disk full"), std::string::npos) << bake.message;
    EXPECT_TRUE(fs::is_empty(out.path()));
  }
}
