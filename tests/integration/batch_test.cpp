// `dmgplace batch` (issue 17): a manifest's tasks run once, resume after kill -9 without losing or
// repeating work, shard into a partition of one run, re-run exactly what a changed input touches,
// and record failures as data. The manifest is small (dmgarm, the eraser, a table corner) and its
// queries stop after a number of rounds, so every run gives the same objectives.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <random>
#include <thread>
#include <set>

#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/tools/batch/batch_state.hpp"
#include "dmgplace/tools/data/procedural_meshes.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;
using ::testing::HasSubstr;

namespace {

struct Batch {
  test::TempDir dir;
  fs::path manifest = dir / "m.yaml";
  explicit Batch(bool with_broken_object = false) {
    test::run_cli({"make-objects", "--out", dir.path()});
    const fs::path data = test::source_dir() / "datasets";
    std::string m = "name: t\nrobots:\n  arm: {urdf: " + (data / "robots/dmgarm/dmgarm.urdf").string() +
                    ", srdf: " + (data / "robots/dmgarm/dmgarm.srdf").string() + ", arm: \"dmgarm_link0:dmgarm_tcp\"}\n" +
                    "objects:\n  eraser: {mesh: eraser.stl}\n";
    if (with_broken_object) {
      test::write_text(dir / "broken.stl", "solid nothing\nendsolid\n");
      m += "  broken: {mesh: broken.stl}\n";
    }
    m += "environments:\n  table: {scene: " + (data / "scenes/table.yaml").string() +
         ", volume: [0.3, -0.3, 0.4, 0.8, 0.3, 0.7], flags: [--resolution, \"0.02\", --margin, \"0.9\", --sdf-resolution, \"0.04\","
         " --band, \"0.25\"]}\n"
         "queries:\n  - name: q\n    robot: arm\n    objects: [eraser" +
         std::string(with_broken_object ? ", broken" : "") +
         "]\n    environments: [table]\n    initial_grasps: {top: [0, 0, 0.0175, 1, 0, 0, 0]}\n"
         "    start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]\n    variants: [full, no-regrasp]\n    seeds: 2\n"
         "    time_limit: 60\n    iterations: 40\n";
    test::write_text(manifest, m);
  }
  tools::ProcessResult run(const fs::path& out, std::vector<test::Arg> extra = {}) const {
    std::vector<test::Arg> args{"batch", manifest, "--out", out};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli(args);
  }
};

// "N ran, M failed, K were done" from the runner's last line.
std::array<int, 3> counts(const std::string& output) {
  std::array<int, 3> c{-1, -1, -1};
  const auto at = output.rfind(" ran, ");
  if (at == std::string::npos) return c;
  const auto line = output.rfind('\n', at) == std::string::npos ? 0 : output.rfind('\n', at) + 1;
  std::sscanf(output.c_str() + line, "%d ran, %d failed, %d were done", &c[0], &c[1], &c[2]);
  return c;
}

// The deterministic columns of a collected dataset, by their digests.
std::map<std::string, std::string> dataset_digest(const fs::path& out) {
  const fs::path d = out / "dataset.h5";
  const auto r = test::run_cli({"batch-collect", out, "--out", d});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  formats::H5Reader h(d);
  std::map<std::string, std::string> m;
  for (const char* c : {"runs/task_id", "runs/solved", "runs/objective", "runs/pose", "runs/grasp_state", "runs/g0"})
    m[c] = h.attribute(c, "sha256").value_or("?");
  return m;
}

std::vector<std::string> litter(const fs::path& out) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    const std::string n = e.path().filename().string();
    if (n.find(".tmp") != std::string::npos || n.ends_with(".lock")) found.push_back(e.path().string());
  }
  return found;
}

// A finished batch: a further run runs nothing, its dataset equals `reference`, nothing is left over.
void expect_complete(const Batch& b, const fs::path& out, const std::map<std::string, std::string>& reference) {
  EXPECT_EQ(counts(b.run(out).output)[0], 0);
  EXPECT_EQ(dataset_digest(out), reference);
  EXPECT_THAT(litter(out), ::testing::IsEmpty());
}

}  // namespace

TEST(Batch, RunsOnceResumesShardsAndCollects) {
  Batch b;
  const fs::path one = b.dir / "one";
  auto r = b.run(one, {"--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(counts(r.output), (std::array<int, 3>{7, 0, 0}));  // 3 bakes, 4 queries
  r = b.run(one);
  EXPECT_EQ(counts(r.output), (std::array<int, 3>{0, 0, 7})) << "a second run runs nothing";
  const auto status = test::run_cli({"batch-status", one, "--json"});
  EXPECT_THAT(status.output, HasSubstr("\"done\": 7"));
  const auto reference = dataset_digest(one);
  EXPECT_EQ(test::run_cli({"validate", one / "dataset.h5"}).exit_code, 0);

  // Three shards, one after another, give exactly one run's tasks, each run once.
  const fs::path sharded = b.dir / "sharded";
  int ran = 0;
  for (const char* s : {"1/3", "2/3", "3/3"}) {
    r = b.run(sharded, {"--shard", s});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    ran += counts(r.output)[0];
  }
  EXPECT_EQ(ran, 7);
  expect_complete(b, sharded, reference);
}

TEST(Batch, KilledAtRandomMomentsLosesAndRepeatsNothing) {
  Batch b;
  const fs::path reference_out = b.dir / "reference";
  ASSERT_EQ(b.run(reference_out).exit_code, 0);
  const auto reference = dataset_digest(reference_out);
  const fs::path out = b.dir / "killed";
  std::mt19937 rng(17);
  for (int k = 0; k < 10; ++k) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int devnull = ::open("/dev/null", O_WRONLY);
      ::dup2(devnull, 1), ::dup2(devnull, 2);
      const std::string cli = test::cli_path(), m = b.manifest.string(), o = out.string();
      ::execl(cli.c_str(), cli.c_str(), "batch", m.c_str(), "--out", o.c_str(), "--jobs", "2", (char*)nullptr);
      ::_exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(50, 1500)(rng)));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
  }
  const auto r = b.run(out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_complete(b, out, reference);
}

TEST(Batch, AChangedMeshReRunsOnlyWhatDependsOnIt) {
  Batch b;
  const fs::path out = b.dir / "out";
  ASSERT_EQ(b.run(out).exit_code, 0);
  tools::write_stl_binary(tools::make_box_mesh({0.12, 0.05, 0.035}), b.dir / "eraser.stl");  // a slightly shorter eraser
  const auto r = b.run(out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(counts(r.output), (std::array<int, 3>{5, 0, 2})) << r.output;  // the object and its 4 queries; robot, table kept
}

TEST(Batch, ABrokenInputFailsOnlyItsOwnTasks) {
  Batch b(true);
  const fs::path out = b.dir / "out";
  const auto r = b.run(out, {"--json"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(counts(r.output), (std::array<int, 3>{7, 5, 0})) << r.output;  // broken bake + its 4 queries
  const auto s = test::run_cli({"batch-status", out});
  EXPECT_EQ(s.exit_code, 1);
  EXPECT_THAT(s.output, HasSubstr("failed  object broken: "));
  EXPECT_THAT(s.output, HasSubstr("broken.stl"));
  EXPECT_THAT(s.output, HasSubstr("needs object broken, which failed"));
  EXPECT_THAT(r.output, HasSubstr("\"ok\":false"));  // --json: one object per finished task
}
