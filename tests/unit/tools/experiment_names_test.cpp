// Names and folders of `dmgplace experiment` / `plot` that a shell would have run: problem names
// are whitelisted where the spec is read, and the charts' PNG step takes any folder as a path.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "dmgplace/tools/experiment/experiment_plots.hpp"
#include "dmgplace/tools/experiment/experiment_spec.hpp"
#include "dmgplace/tools/system/process.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;
using namespace dmgplace::tools;

namespace {
// This process's working folder, restored on every way out: a shell started by the code under
// test would create its file here.
struct InFolder {
  fs::path before = fs::current_path();
  explicit InFolder(const fs::path& p) { fs::current_path(p); }
  ~InFolder() { fs::current_path(before); }
  InFolder(const InFolder&) = delete;
  InFolder& operator=(const InFolder&) = delete;
};

// Every file or folder under `dir` named `name`.
int count_named(const fs::path& dir, const std::string& name) {
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) n += e.path().filename() == name;
  return n;
}

// A finished run as `dmgplace experiment` leaves it: DIR/runs/PROBLEM/VARIANT/seed_1/result.json.
void write_run(const fs::path& dir, const std::string& problem, const std::string& variant) {
  const fs::path run = dir / "runs" / problem / variant / "seed_1";
  fs::create_directories(run);
  test::write_text(run / "result.json", R"({"solved": true, "seconds": 2.0, "query": {"time_limit": 2},
    "improvements": [{"time": 0.4, "objective": 3.0}, {"time": 1.5, "objective": 2.5}],
    "best": {"in_hand": []}, "counters": {"samples": 100, "goals": 4}})");
}
}  // namespace

// Issue: a problem name became part of a shell command line. Names are now a whitelist, and the
// error names the file, the element and the name.
TEST(ExperimentNames, ProblemNamesThatWouldRunACommandAreRejected) {
  test::TempDir dir;
  InFolder in_dir(dir.path());
  test::write_text(dir / "q.yaml", "robot: r.h5\n");
  const fs::path spec = dir / "s.yaml";
  // The second one has no space: the old check ('/', '\\', ' ') let it through.
  for (const std::string name :
       {"x'$(touch PWNED)'", "x$(touch${IFS}PWNED)", "a`touch PWNED`", "a/b", "..", ".", "é", "a;b"}) {
    SCOPED_TRACE(name);
    test::write_text(spec, "problems:\n  - {name: a, query: q.yaml}\n  - {name: \"" + name + "\", query: q.yaml}\n");
    const std::string e = test::error_of([&] { read_experiment_spec(spec); });
    EXPECT_NE(e.find(spec.string() + ": problems[1].name: '" + name + "'"), std::string::npos) << e;
    EXPECT_NE(e.find("letters, digits, '.', '_' and '-'"), std::string::npos) << e;
  }
  EXPECT_EQ(count_named(dir.path(), "PWNED"), 0);
  // The whitelist itself is accepted.
  test::write_text(spec, "problems:\n  - {name: Cabinet_bottle-side.v2, query: q.yaml}\n");
  EXPECT_EQ(read_experiment_spec(spec).problems.at(0).name, "Cabinet_bottle-side.v2");
}

// Issue: `dmgplace plot` ran `rsvg-convert -o '<png>' '<svg>'` through a shell, so a folder named
// '$(touch PWNED2)' ran touch. Now it is only a folder; its charts are drawn as usual.
TEST(ExperimentNames, PlotsInAFolderNamedLikeACommand) {
  test::TempDir dir;
  const fs::path exp = dir / "'$(touch PWNED2)'";
  write_run(exp, "side", "full");
  write_run(exp, "side", "no-regrasp");
  std::vector<fs::path> written;
  {
    InFolder in_dir(dir.path());
    EXPECT_NO_THROW(written = plot_experiment(exp));
  }
  EXPECT_EQ(count_named(dir.path(), "PWNED2"), 0) << "a shell ran the folder's name";
  EXPECT_FALSE(fs::exists(fs::current_path() / "PWNED2"));
  const bool png = find_executable("rsvg-convert").has_value();
  EXPECT_EQ(written.size(), png ? 5u : 3u);  // curves.csv, 2 charts as SVG (and PNG)
  for (const char* chart : {"side_objective", "side_solved"}) {
    EXPECT_NE(test::read_text(exp / "plots" / (std::string(chart) + ".svg")).find("<svg"), std::string::npos) << chart;
    if (png) {
      EXPECT_TRUE(test::read_text(exp / "plots" / (std::string(chart) + ".png")).starts_with("\x89PNG")) << chart;
    }
  }
}

// Folder names under runs/ name the charts, so plot checks them as the spec reader does, before
// writing anything.
TEST(ExperimentNames, PlotRejectsAProblemFolderWithAnUnsafeName) {
  test::TempDir dir;
  write_run(dir.path(), "a b", "full");
  const std::string e = test::error_of([&] { plot_experiment(dir.path()); });
  EXPECT_NE(e.find((dir / "runs").string() + ": problem folder: 'a b'"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir / "plots"));
}
