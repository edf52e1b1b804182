// `dmgplace experiment` and `dmgplace plot` end to end on the built-in cabinet: a small grid runs,
// writes a trace per run and summary.csv, resumes without redoing finished runs, reruns a run
// whose result was removed, and the plot step draws every problem's charts.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {
test::ProcessResult run(const std::vector<test::Arg>& args) { return test::run_cli(args); }

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
  ASSERT_EQ(run({"make-objects", "--out", dir.path()}).exit_code, 0);
  ASSERT_EQ(run({"bake-robot", data / "robots/dmgarm/dmgarm.urdf", "--srdf", data / "robots/dmgarm/dmgarm.srdf",
                 "--arm", "dmgarm_link0:dmgarm_tcp", "--out", art / "dmgarm.h5"})
                .exit_code,
            0);
  ASSERT_EQ(run({"bake-object", dir / "bottle.stl", "--mass", "0.15", "--out", art / "bottle.h5"}).exit_code, 0);
  const std::string volume = test::builtin_volume("cabinet");
  ASSERT_EQ(run({"bake-env", data / "scenes/cabinet.yaml", "--volume", volume, "--margin", "0.9", "--sdf-resolution",
                 "0.02", "--band", "0.25", "--out", art / "cabinet.h5"})
                .exit_code,
            0);
  test::write_text(dir / "spec.yaml",
                   "name: small\ntime_limit: 1\nruns: 2\nthreads: 2\nreport_times: [0.5, 1]\nproblems:\n"
                   "  - {name: side, query: " +
                       (data / "queries/cabinet_bottle_side.yaml").string() + ", variants: [full, no-regrasp]}\n");
  const std::vector<test::Arg> cmd = {"experiment", dir / "spec.yaml", "--artifacts", art, "--out", out, "--jobs", "2"};
  auto first = run(cmd);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("4/4"), std::string::npos) << "progress must count runs: " << first.output;
  for (const char* variant : {"full", "no-regrasp"})
    for (int seed : {1, 2}) {
      const fs::path run_dir = out / "runs/side" / variant / ("seed_" + std::to_string(seed));
      EXPECT_TRUE(fs::exists(run_dir / "result.json")) << run_dir;
      EXPECT_GE(csv_rows(run_dir / "trace.csv"), 1) << run_dir;
      // The spec's planner threads are honoured, not forced to 0.
      EXPECT_NE(test::read_text(run_dir / "result.json").find("\"threads\": 2"), std::string::npos) << run_dir;
    }
  EXPECT_EQ(csv_rows(out / "summary.csv"), 4);
  const std::string header = test::read_text(out / "summary.csv").substr(0, 200);
  EXPECT_NE(header.find("objective_at_0.5s"), std::string::npos) << header;

  // Resumed: nothing left to do, results untouched.
  const auto stamp = fs::last_write_time(out / "runs/side/full/seed_1/result.json");
  auto second = run(cmd);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_NE(second.output.find("0 run now, 4 done before"), std::string::npos) << second.output;
  EXPECT_EQ(fs::last_write_time(out / "runs/side/full/seed_1/result.json"), stamp);
  // A removed result is run again, and only that one.
  fs::remove(out / "runs/side/no-regrasp/seed_2/result.json");
  auto third = run(cmd);
  ASSERT_EQ(third.exit_code, 0) << third.output;
  EXPECT_NE(third.output.find("1 run now, 3 done before"), std::string::npos) << third.output;
  EXPECT_TRUE(fs::exists(out / "runs/side/no-regrasp/seed_2/result.json"));
  EXPECT_EQ(fs::last_write_time(out / "runs/side/full/seed_1/result.json"), stamp);

  auto plot = run({"plot", out});
  ASSERT_EQ(plot.exit_code, 0) << plot.output;
  for (const char* chart : {"side_objective.svg", "side_solved.svg"}) {
    const std::string svg = test::read_text(out / "plots" / chart);
    EXPECT_NE(svg.find("<svg"), std::string::npos) << chart;
    EXPECT_NE(svg.find("full"), std::string::npos) << chart << ": a legend entry per variant";
    EXPECT_NE(svg.find("no-regrasp"), std::string::npos) << chart;
  }
  EXPECT_GT(csv_rows(out / "plots/curves.csv"), 10);

  // Issue: the PNG step ran a shell command line holding the folder's path. A copy of the
  // finished experiment in a folder named like a command plots as usual and runs nothing; the
  // plot runs in `dir`, where a shell's touch would have left PWNED2.
  const fs::path odd = dir / "'$(touch PWNED2)'";
  fs::copy(out, odd, fs::copy_options::recursive);
  fs::remove_all(odd / "plots");
  test::ProcessOptions in_dir;
  in_dir.cwd = dir.path();
  in_dir.stderr_to = test::StderrTo::merge;
  const auto odd_plot = tools::run_process({test::cli_path(), "plot", odd.string()}, in_dir);
  ASSERT_EQ(odd_plot.exit_code, 0) << odd_plot.output;
  const bool png = tools::find_executable("rsvg-convert").has_value();
  for (const char* chart : {"side_objective", "side_solved"}) {
    EXPECT_NE(test::read_text(odd / "plots" / (std::string(chart) + ".svg")).find("<svg"), std::string::npos) << chart;
    EXPECT_EQ(fs::exists(odd / "plots" / (std::string(chart) + ".png")), png)
        << chart << ": PNG when rsvg-convert is installed";
  }
  EXPECT_FALSE(fs::exists(dir / "PWNED2"));

  // A spec naming a missing query fails before running anything, naming the file.
  test::write_text(dir / "bad.yaml", "problems:\n  - {name: x, query: nowhere.yaml}\n");
  auto bad = run({"experiment", dir / "bad.yaml", "--out", dir / "bad"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("nowhere.yaml"), std::string::npos) << bad.output;
}

// Issue: a problem name became part of a shell command line (the PNG step of `plot`). The spec is
// now rejected before anything runs, naming the name, and nothing runs the command.
TEST(ExperimentCli, AProblemNameHoldingACommandIsRejected) {
  test::TempDir dir;
  const fs::path query = test::source_dir() / "datasets/queries/cabinet_bottle_side.yaml";
  for (const std::string name : {"x'$(touch PWNED)'", "x$(touch${IFS}PWNED)"}) {
    SCOPED_TRACE(name);
    test::write_text(dir / "spec.yaml", "time_limit: 1\nruns: 1\nproblems:\n  - {name: \"" + name +
                                            "\", query: " + query.string() + "}\n");
    test::ProcessOptions in_dir;  // where a shell's touch would leave PWNED
    in_dir.cwd = dir.path();
    in_dir.stderr_to = test::StderrTo::merge;
    const auto r = tools::run_process(
        {test::cli_path(), "experiment", (dir / "spec.yaml").string(), "--out", (dir / "exp").string()}, in_dir);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("problems[0].name: '" + name + "'"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "exp" / "runs")) << "nothing may run";
  }
  for (const auto& e : fs::recursive_directory_iterator(dir.path()))
    EXPECT_NE(e.path().filename(), "PWNED") << e.path();
}
