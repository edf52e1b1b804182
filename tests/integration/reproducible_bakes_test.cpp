// Issue 19, item 9: bakes are bit-for-bit reproducible apart from the header's time stamp and
// paths. The same inputs are baked in two folders whose paths differ in length (the placement
// faces once followed the path: CGAL's facet order follows heap addresses) and with one CPU or
// all of them (`taskset`), and every dataset's SHA-256 must agree.
#include <gtest/gtest.h>

#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/tools/system/process.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {

// dataset -> sha256 of its content: equal maps mean equal data.
std::map<std::string, std::string> digests(const fs::path& artifact) {
  formats::H5Reader r(artifact);
  std::map<std::string, std::string> out;
  for (const auto& name : r.dataset_names()) out[name] = r.attribute(name, "sha256").value_or("?");
  EXPECT_FALSE(out.empty()) << artifact;
  return out;
}

void run_ok(const std::vector<test::Arg>& args, bool one_cpu = false) {
  std::vector<std::string> argv;
  if (one_cpu) argv = {"taskset", "-c", "0"};
  argv.push_back(test::cli_path());
  for (const auto& a : args) argv.push_back(a.text);
  tools::ProcessOptions o;
  o.stderr_to = tools::StderrTo::merge;
  const auto r = tools::run_process(argv, o);
  ASSERT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace

TEST(ReproducibleBakes, SameInputsGiveTheSameDatasetsWhateverThePathAndThreads) {
  if (!tools::find_executable("taskset")) GTEST_SKIP() << "no taskset (util-linux)";
  test::TempDir dir;
  const fs::path data = test::source_dir() / "datasets";
  const fs::path a = dir / "a";
  const fs::path b = dir / "a_folder_with_a_much_longer_name_than_the_other_one" / "and_deeper_still";
  for (const auto& d : {a, b}) {
    fs::create_directories(d);
    run_ok({"make-objects", "--out", d});
  }
  // The STL files themselves are byte-identical (our own writer).
  ASSERT_EQ(test::read_text(a / "bottle.stl"), test::read_text(b / "bottle.stl"));
  for (const char* object : {"bottle", "eraser"}) {
    SCOPED_TRACE(object);
    run_ok({"bake-object", a / (std::string(object) + ".stl"), "--out", a / (std::string(object) + ".h5")});
    run_ok({"bake-object", b / (std::string(object) + ".stl"), "--out", b / (std::string(object) + ".h5")}, true);
    EXPECT_EQ(digests(a / (std::string(object) + ".h5")), digests(b / (std::string(object) + ".h5")));
  }
  run_ok({"bake-robot", data / "robots/dmgarm/dmgarm.urdf", "--srdf", data / "robots/dmgarm/dmgarm.srdf", "--arm",
          "dmgarm_link0:dmgarm_tcp", "--out", a / "arm.h5"});
  run_ok({"bake-robot", data / "robots/dmgarm/dmgarm.urdf", "--srdf", data / "robots/dmgarm/dmgarm.srdf", "--arm",
          "dmgarm_link0:dmgarm_tcp", "--out", b / "arm.h5"},
         true);
  EXPECT_EQ(digests(a / "arm.h5"), digests(b / "arm.h5"));
  for (const fs::path& d : {a, b})
    run_ok({"bake-env", data / "scenes/table.yaml", "--volume", "0.3,-0.3,0.4,0.8,0.3,0.7", "--resolution", "0.02",
            "--margin", "0.3", "--sdf-resolution", "0.04", "--out", d / "table.h5"},
           d == b);
  EXPECT_EQ(digests(a / "table.h5"), digests(b / "table.h5"));
}
