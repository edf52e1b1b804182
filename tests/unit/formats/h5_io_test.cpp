#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/h5_writer.hpp"
#include "test_support.hpp"

#ifndef FLIP_STRIDE
#define FLIP_STRIDE 7
#endif
namespace fs = std::filesystem;
using namespace dmgplace::formats;

namespace {
ArtifactHeader header(const std::string& schema = "dmgplace.test", int version = 3) {
  ArtifactHeader h;
  h.schema = schema;
  h.schema_version = version;
  h.parameters_json = R"({"a":1})";
  h.inputs = {{"in/a.stl", std::string(64, 'a')}, {"b.urdf", std::string(64, 'b')}};
  return h;
}

std::vector<float> field_values() {
  std::vector<float> f(6000);
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = float(std::cos(0.01 * double(i)));
  return f;
}

void write_sample(const fs::path& p, double offset = 0) {
  H5Writer w(p, header());
  std::vector<double> v(3000);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(double(i)) + offset;
  w.write("g/values", std::span<const double>(v), {1000, 3});
  std::vector<std::int32_t> idx{1, 2, 3, 4, 5, 6};
  w.write("g/sub/idx", std::span<const std::int32_t>(idx), {2, 3});
  w.write("empty", std::span<const double>(), {0, 3});
  w.write_strings("names", {"alpha", "", "gamma"});
  w.write_contiguous("g/field", std::span<const float>(field_values()), {10, 20, 30});
  w.commit();
}

bool is_error_naming(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
  } catch (const dmgplace::Error& e) {
    return std::string(e.what()).find(needle) != std::string::npos;
  }
  return false;
}
}  // namespace

TEST(H5IO, RoundTripKeepsHeaderValuesAndShapes) {
  dmgplace::test::TempDir dir;
  write_sample(dir / "a.h5");
  H5Reader r(dir / "a.h5");
  EXPECT_EQ(r.header().schema, "dmgplace.test");
  EXPECT_EQ(r.header().schema_version, 3);
  EXPECT_EQ(r.header().parameters_json, R"({"a":1})");
  ASSERT_EQ(r.header().inputs.size(), 2u);
  EXPECT_EQ(r.header().inputs[0].path, "in/a.stl");
  EXPECT_EQ(r.header().inputs[1].sha256, std::string(64, 'b'));
  EXPECT_FALSE(r.header().tool_version.empty());
  auto v = r.read_f64("g/values", {1000, 3});
  ASSERT_EQ(v.data.size(), 3000u);
  for (std::size_t i = 0; i < v.data.size(); ++i) ASSERT_DOUBLE_EQ(v.data[i], std::sin(double(i)));
  auto idx = r.read_i32("g/sub/idx", {-1, 3});
  EXPECT_EQ(idx.rows(), 2u);
  EXPECT_EQ(idx(1, 2), 6);
  EXPECT_EQ(r.read_f64("empty", {-1, 3}).rows(), 0u);
  EXPECT_EQ(r.read_strings("names"), (std::vector<std::string>{"alpha", "", "gamma"}));
  EXPECT_EQ(r.read_f32("g/field", {10, 20, 30}).data, field_values());  // the contiguous, unfiltered layout
  EXPECT_TRUE(r.verify_all_checksums().empty());
  EXPECT_EQ(r.dataset_names(), (std::vector<std::string>{"empty", "g/field", "g/sub/idx", "g/values", "names"}));
}

TEST(H5IO, ShapeTypeAndMissingDatasetErrorsNameFileAndDataset) {
  dmgplace::test::TempDir dir;
  write_sample(dir / "a.h5");
  H5Reader r(dir / "a.h5");
  EXPECT_TRUE(is_error_naming([&] { r.read_f64("g/values", {1000, 4}); }, "g/values"));
  EXPECT_TRUE(is_error_naming([&] { r.read_f64("g/values", {-1}); }, "wrong shape"));
  EXPECT_TRUE(is_error_naming([&] { r.read_i32("g/values", {-1, 3}); }, "wrong element type"));
  EXPECT_TRUE(is_error_naming([&] { r.read_f64("nope/x", {-1}); }, "missing dataset"));
  EXPECT_TRUE(is_error_naming(
      [&] {
        r.read_f64("g/values", {1000, 3});
        r.read_f64("nope", {1});
      },
      "a.h5"));
}

TEST(H5IO, SchemaMismatchIsReported) {
  dmgplace::test::TempDir dir;
  write_sample(dir / "a.h5");
  H5Reader r(dir / "a.h5");
  EXPECT_NO_THROW(r.require_schema("dmgplace.test", 3));
  EXPECT_TRUE(is_error_naming([&] { r.require_schema("dmgplace.test", 4); }, "schema_version"));
  EXPECT_TRUE(is_error_naming([&] { r.require_schema("dmgplace.robot", 3); }, "expected 'dmgplace.robot'"));
}

TEST(H5IO, NonHdf5AndEmptyAndMissingFilesAreRejectedClearly) {
  dmgplace::test::TempDir dir;
  dmgplace::test::write_text(dir / "text.h5", "this is not hdf5 at all");
  dmgplace::test::write_text(dir / "empty.h5", "");
  EXPECT_TRUE(is_error_naming([&] { H5Reader r(dir / "text.h5"); }, "not an HDF5 file"));
  EXPECT_TRUE(is_error_naming([&] { H5Reader r(dir / "empty.h5"); }, "empty file"));
  EXPECT_TRUE(is_error_naming([&] { H5Reader r(dir / "none.h5"); }, "no such file"));
}

TEST(H5IO, WriterWithoutCommitLeavesOldFileAndNoTemporary) {
  dmgplace::test::TempDir dir;
  write_sample(dir / "a.h5", 0.0);
  const std::string before = dmgplace::test::read_text(dir / "a.h5");
  {
    H5Writer w(dir / "a.h5", header());
    std::vector<double> v(10, 42.0);
    w.write("g/values", std::span<const double>(v), {10});
    EXPECT_TRUE(fs::exists(w.temp_path()));
    // destroyed without commit(): an interrupted bake
  }
  EXPECT_EQ(dmgplace::test::read_text(dir / "a.h5"), before);
  std::size_t files = 0;
  for (auto& e : fs::directory_iterator(dir.path())) files += e.is_regular_file();
  EXPECT_EQ(files, 1u) << "the temporary file must be gone";
}

TEST(H5IO, CommitReplacesTheOldFile) {
  dmgplace::test::TempDir dir;
  write_sample(dir / "a.h5", 0.0);
  write_sample(dir / "a.h5", 5.0);
  H5Reader r(dir / "a.h5");
  EXPECT_DOUBLE_EQ(r.read_f64("g/values", {1000, 3}).data[0], 5.0);
}

TEST(H5IO, OutputIntoMissingFolderIsAClearError) {
  dmgplace::test::TempDir dir;
  EXPECT_TRUE(is_error_naming([&] { H5Writer w(dir / "no/such/a.h5", header()); }, "output folder does not exist"));
}

// Property: whatever single byte is flipped, a reader either reports an error or returns exactly
// the original content; never silent garbage.
TEST(H5IO, AnyFlippedByteIsDetectedOrHarmless) {
  dmgplace::test::TempDir dir;
  write_sample(dir / "a.h5");
  const std::string original = dmgplace::test::read_text(dir / "a.h5");
  std::mt19937 rng(1234);
  std::vector<std::size_t> positions;
  for (std::size_t i = 0; i < original.size(); i += FLIP_STRIDE) positions.push_back(i);  // dense coverage of metadata
  int detected = 0, harmless = 0;
  for (std::size_t pos : positions) {
    std::string bytes = original;
    bytes[pos] = char(bytes[pos] ^ (1 << (rng() % 8)));
    dmgplace::test::write_text(dir / "b.h5", bytes);
    try {
      H5Reader r(dir / "b.h5");
      auto v = r.read_f64("g/values", {1000, 3});
      auto idx = r.read_i32("g/sub/idx", {2, 3});
      auto names = r.read_strings("names");
      // The contiguous dataset has no Fletcher32: its SHA-256 alone must catch a flipped byte.
      auto field = r.read_f32("g/field", {10, 20, 30});
      if (r.header().schema != "dmgplace.test" || r.header().schema_version != 3)
        throw dmgplace::Error("header changed");
      if (r.header().parameters_json != R"({"a":1})" || r.header().inputs.size() != 2 ||
          r.header().inputs[0].path != "in/a.stl")
        throw dmgplace::Error("header changed");
      for (std::size_t i = 0; i < v.data.size(); ++i)
        ASSERT_DOUBLE_EQ(v.data[i], std::sin(double(i))) << "byte " << pos;
      ASSERT_EQ(idx(1, 2), 6) << "byte " << pos;
      ASSERT_EQ(names.size(), 3u) << "byte " << pos;
      ASSERT_EQ(field.data, field_values()) << "byte " << pos;
      ++harmless;
    } catch (const dmgplace::Error& e) {
      ++detected;
    }
  }
  EXPECT_GT(detected, 0);
  RecordProperty("detected", detected);
  RecordProperty("harmless", harmless);
}

TEST(H5IO, Utf8StringsRoundTripAsHdf5StringsWithTheirDigest) {
  dmgplace::test::TempDir dir;
  const std::vector<std::string> names{"panda", "", "bouteille \xC3\xA0 lait", "a,\"b\""};
  {
    H5Writer w(dir / "s.h5", header());
    w.ordered_group("t");
    w.write_utf8_strings("t/names", names);
    w.write_utf8_strings("t/none", {});
    EXPECT_TRUE(is_error_naming([&] { w.write_utf8_strings("nul", {std::string("a\0b", 3)}); },
                                "nul[0]: string contains a NUL byte"));
    EXPECT_TRUE(is_error_naming(
        [&] {
          w.write_utf8_strings("bad", {"ok", "\xC3("});
        },
        "bad[1]: string is not valid UTF-8"));
    w.commit();
  }
  H5Reader r(dir / "s.h5");
  EXPECT_EQ(r.read_utf8_strings("t/names"), names);
  EXPECT_TRUE(r.read_utf8_strings("t/none").empty());
  EXPECT_EQ(r.shape("t/names"), (std::vector<std::size_t>{4}));
  EXPECT_TRUE(r.verify_all_checksums().empty());
  EXPECT_TRUE(is_error_naming([&] { r.read_i64("t/names", {-1}); }, "t/names: wrong element type"));
  EXPECT_TRUE(is_error_naming([&] { r.read_utf8_strings("g"); }, "g: missing dataset"));
}
