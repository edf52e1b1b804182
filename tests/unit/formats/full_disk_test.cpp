// A writer running out of disk: the error names the file and says the write failed (disk full),
// nothing is left behind (no partial artifact, no temporary file) and an artifact that was there
// before is untouched.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_writer.hpp"
#include "full_disk.hpp"
#include "test_support.hpp"

namespace dmgplace::formats {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

// `size` bytes of noise; 1 MiB is more than deflate can shrink below any of the limits used here.
void write_artifact(const std::filesystem::path& target, std::size_t size = 1 << 20) {
  ArtifactHeader h;
  h.schema = "dmgplace.test";
  h.schema_version = 1;
  std::vector<std::uint8_t> bytes(size);
  std::mt19937 rng(5);
  for (auto& b : bytes) b = std::uint8_t(rng());
  H5Writer w(target, h);
  w.write("noise", std::span<const std::uint8_t>(bytes), {bytes.size()});
  w.commit();
}

TEST(FullDisk, H5WriterOnAFullTmpfsFailsAndLeavesNothing) {
  test::SmallDisk disk("64k");
  if (!disk.mounted()) GTEST_SKIP() << disk.why_not() << "; FullDisk.H5WriterOverTheFileSizeLimit* covers the same";
  const auto target = disk / "a.h5";
  write_artifact(target, 100);
  const std::string before = test::read_text(target);
  EXPECT_THAT(test::error_of([&] { write_artifact(target); }),
              AllOf(HasSubstr(target.string()), HasSubstr("disk full")));
  EXPECT_THAT(disk.files_except("a.h5"), IsEmpty());
  EXPECT_TRUE(test::read_text(target) == before) << "the previous artifact was replaced";
}

TEST(FullDisk, H5WriterOverTheFileSizeLimitFailsAndLeavesNothing) {
  test::TempDir dir;
  const auto target = dir / "a.h5";
  write_artifact(target, 100);
  const std::string before = test::read_text(target);
  const auto r = test::with_file_size_limit(64 * 1024, [&] { write_artifact(target); });
  EXPECT_EQ(r.code, 0) << r.message;
  EXPECT_THAT(r.message, AllOf(HasSubstr(target.string()), HasSubstr("disk full")));
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) names.push_back(e.path().filename().string());
  EXPECT_THAT(names, ::testing::ElementsAre("a.h5"));
  EXPECT_TRUE(test::read_text(target) == before) << "the previous artifact was replaced";
}

}  // namespace
}  // namespace dmgplace::formats
