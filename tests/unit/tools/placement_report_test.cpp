// `dmgplace place`'s output files when the disk fills up: the error names the file and says the
// write failed, the hidden temporary file is removed and the previous result stays as it was.
#include "dmgplace/tools/placement/placement_report.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dmgplace/tools/io/urdf_reader.hpp"
#include "full_disk.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::UnorderedElementsAre;

runtime::Kinematics dmgarm() {
  return runtime::Kinematics(read_urdf(test::source_dir() / "datasets/robots/dmgarm/dmgarm.urdf"), "dmgarm_link0",
                             "dmgarm_tcp");
}

runtime::PlacementResult no_solution(const std::string& reason) {
  runtime::PlacementResult r;
  r.reason = reason;
  return r;
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

TEST(PlacementReport, FailedWriteOnAFullTmpfsRemovesItsTemporaryFile) {
  test::SmallDisk disk("64k");
  if (!disk.mounted())
    GTEST_SKIP() << disk.why_not() << "; PlacementReport.FailedWriteOverTheFileSizeLimit* covers the same";
  const auto kin = dmgarm();
  const fs::path out = disk / "out";
  write_placement_result(out, PlacementQueryFile{}, no_solution("first"), kin);
  const std::string before = test::read_text(out / "result.json");
  disk.fill();
  EXPECT_THAT(test::error_of([&] { write_placement_result(out, PlacementQueryFile{}, no_solution("second"), kin); }),
              AllOf(HasSubstr((out / "trace.csv").string()), HasSubstr("write failed (disk full")));
  EXPECT_THAT(names_in(out), UnorderedElementsAre("result.json", "trace.csv", "path.csv", "trajectory.json"));
  EXPECT_EQ(test::read_text(out / "result.json"), before);
}

TEST(PlacementReport, FailedWriteOverTheFileSizeLimitRemovesItsTemporaryFile) {
  test::TempDir dir;
  const auto kin = dmgarm();
  const fs::path out = dir / "out";
  // Every file is larger than 64 bytes: the first, trace.csv, already fails.
  const auto r =
      test::with_file_size_limit(64, [&] { write_placement_result(out, PlacementQueryFile{}, no_solution("x"), kin); });
  EXPECT_EQ(r.code, 0) << r.message;
  EXPECT_THAT(r.message, AllOf(HasSubstr((out / "trace.csv").string()), HasSubstr("write failed (disk full")));
  EXPECT_TRUE(fs::is_empty(out)) << "left: " << ::testing::PrintToString(names_in(out));
}

// Issue 19: result.json marks a run complete (experiment resumes past runs that have it), so it
// is written last: when path.csv cannot be written, there is no result.json.
TEST(PlacementReport, ResultJsonIsWrittenLast) {
  test::TempDir dir;
  const auto kin = dmgarm();
  const fs::path out = dir / "out";
  fs::create_directories(out / "path.csv" / "blocker");  // a non-empty folder: the rename onto it fails
  EXPECT_THAT(test::error_of([&] { write_placement_result(out, PlacementQueryFile{}, no_solution("x"), kin); }),
              HasSubstr((out / "path.csv").string()));
  EXPECT_TRUE(fs::exists(out / "trace.csv"));
  EXPECT_FALSE(fs::exists(out / "result.json"));
  EXPECT_THAT(names_in(out), UnorderedElementsAre("trace.csv", "path.csv"));  // no temporary file left
}

}  // namespace
}  // namespace dmgplace::tools
