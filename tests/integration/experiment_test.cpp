// `dmgplace experiment` and `dmgplace plot` end to end on the built-in cabinet: a small grid runs,
// writes a trace per run and summary.csv, resumes without redoing finished runs, reruns a run
// whose result was removed, and the plot step draws every problem's charts.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {
test::ShellResult run(const std::string& args) { return test::run_cli(args); }
std::string q(const fs::path& p) { return test::quoted(p); }

int csv_rows(const fs::path& p) {
  std::ifstream f(p);
  int n = -1;  // the header
  for (std::string line; std::getline(f, line);) n += !line.empty();
  return n;
}
}  // namespace

TEST(ExperimentCli, RunsResumesAndPlotsASmallGrid) {
  test::TempDir dir;
  const fs::path data = test::source_dir() / "datasets", art = dir / "artifacts", out = dir / "exp";
  fs::create_directories(art);
  ASSERT_EQ(run("make-objects --out " + q(dir.path())).code, 0);
  ASSERT_EQ(run("bake-robot " + q(data / "robots/dmgarm/dmgarm.urdf") + " --srdf " + q(data / "robots/dmgarm/dmgarm.srdf") +
                " --arm dmgarm_link0:dmgarm_tcp --out " + q(art / "dmgarm.h5")).code, 0);
  ASSERT_EQ(run("bake-object " + q(dir / "bottle.stl") + " --mass 0.15 --out " + q(art / "bottle.h5")).code, 0);
  std::string volume = test::read_text(data / "scenes/cabinet.volume");
  volume.erase(volume.find_last_not_of(" \n\r") + 1);
  ASSERT_EQ(run("bake-env " + q(data / "scenes/cabinet.yaml") + " --volume " + volume +
                " --margin 0.9 --sdf-resolution 0.02 --band 0.25 --out " + q(art / "cabinet.h5")).code, 0);
  test::write_text(dir / "spec.yaml",
                   "name: small\ntime_limit: 1\nruns: 2\nreport_times: [0.5, 1]\nproblems:\n"
                   "  - {name: side, query: " + (data / "queries/cabinet_bottle_side.yaml").string() +
                   ", variants: [full, no-regrasp]}\n");
  const std::string cmd = "experiment " + q(dir / "spec.yaml") + " --artifacts " + q(art) + " --out " + q(out) + " --jobs 2";
  auto first = run(cmd);
  ASSERT_EQ(first.code, 0) << first.out;
  EXPECT_NE(first.out.find("4/4"), std::string::npos) << "progress must count runs: " << first.out;
  for (const char* variant : {"full", "no-regrasp"})
    for (int seed : {1, 2}) {
      const fs::path run_dir = out / "runs/side" / variant / ("seed_" + std::to_string(seed));
      EXPECT_TRUE(fs::exists(run_dir / "result.json")) << run_dir;
      EXPECT_GE(csv_rows(run_dir / "trace.csv"), 1) << run_dir;
    }
  EXPECT_EQ(csv_rows(out / "summary.csv"), 4);
  const std::string header = test::read_text(out / "summary.csv").substr(0, 200);
  EXPECT_NE(header.find("objective_at_0.5s"), std::string::npos) << header;

  // Resumed: nothing left to do, results untouched.
  const auto stamp = fs::last_write_time(out / "runs/side/full/seed_1/result.json");
  auto second = run(cmd);
  ASSERT_EQ(second.code, 0) << second.out;
  EXPECT_NE(second.out.find("0 run now, 4 done before"), std::string::npos) << second.out;
  EXPECT_EQ(fs::last_write_time(out / "runs/side/full/seed_1/result.json"), stamp);
  // A removed result is run again, and only that one.
  fs::remove(out / "runs/side/no-regrasp/seed_2/result.json");
  auto third = run(cmd);
  ASSERT_EQ(third.code, 0) << third.out;
  EXPECT_NE(third.out.find("1 run now, 3 done before"), std::string::npos) << third.out;
  EXPECT_TRUE(fs::exists(out / "runs/side/no-regrasp/seed_2/result.json"));
  EXPECT_EQ(fs::last_write_time(out / "runs/side/full/seed_1/result.json"), stamp);

  auto plot = run("plot " + q(out));
  ASSERT_EQ(plot.code, 0) << plot.out;
  for (const char* chart : {"side_objective.svg", "side_solved.svg"}) {
    const std::string svg = test::read_text(out / "plots" / chart);
    EXPECT_NE(svg.find("<svg"), std::string::npos) << chart;
    EXPECT_NE(svg.find("full"), std::string::npos) << chart << ": a legend entry per variant";
    EXPECT_NE(svg.find("no-regrasp"), std::string::npos) << chart;
  }
  EXPECT_GT(csv_rows(out / "plots/curves.csv"), 10);
  // A spec naming a missing query fails before running anything, naming the file.
  test::write_text(dir / "bad.yaml", "problems:\n  - {name: x, query: nowhere.yaml}\n");
  auto bad = run("experiment " + q(dir / "bad.yaml") + " --out " + q(dir / "bad"));
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.out.find("nowhere.yaml"), std::string::npos) << bad.out;
}
