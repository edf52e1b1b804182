// read_pcd / read_scan_scene on PCD files written here (ascii and binary), broken ones rejected.
#include "dmgplace/tools/io/pcd_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

#include "dmgplace/formats/error.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

using test::TempDir;
using test::write_text;
using ::testing::HasSubstr;

std::string header(const std::string& fields, int points, const std::string& data, int width = -1) {
  std::string sizes, types, counts;
  for (std::size_t i = 0, n = 1 + std::size_t(std::count(fields.begin(), fields.end(), ' ')); i < n; ++i)
    sizes += " 4", types += " F", counts += " 1";
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " + fields + "\nSIZE" + sizes + "\nTYPE" +
         types + "\nCOUNT" + counts + "\nWIDTH " + std::to_string(width < 0 ? points : width) +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(points) + "\nDATA " + data + "\n";
}

std::string binary_body(const std::vector<float>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
}

using ::dmgplace::test::error_of;

TEST(PcdReader, AsciiDropsNonFinitePoints) {
  TempDir dir;
  write_text(dir / "a.pcd", header("x y z", 5, "ascii") + "1 2 3\nnan nan nan\n4 5 6\n7 inf 9\n-1.5 0.25 1e-3\n");
  const RowMatrixX3d p = read_pcd(dir / "a.pcd");
  ASSERT_EQ(p.rows(), 3);
  EXPECT_TRUE(p.row(0).isApprox(Eigen::RowVector3d(1, 2, 3)));
  EXPECT_TRUE(p.row(1).isApprox(Eigen::RowVector3d(4, 5, 6)));
  EXPECT_TRUE(p.row(2).isApprox(Eigen::RowVector3d(-1.5, 0.25, 1e-3), 1e-6));
  EXPECT_TRUE(p.allFinite());
}

TEST(PcdReader, BinaryWithExtraFieldsRoundTrips) {
  // Property: random clouds written as binary x y z rgb come back as their finite x y z.
  TempDir dir;
  std::srand(5);
  for (int trial = 0; trial < 10; ++trial) {
    const int n = 1 + std::rand() % 50;
    std::vector<float> values;
    std::vector<Eigen::RowVector3d> expected;
    for (int i = 0; i < n; ++i) {
      const bool hole = std::rand() % 4 == 0;
      const float x = hole ? std::numeric_limits<float>::quiet_NaN() : float(std::rand() % 1000) / 100.f;
      const float y = float(std::rand() % 1000) / 100.f - 5.f, z = float(i);
      values.insert(values.end(), {x, y, z, 0.f});
      if (!hole) expected.emplace_back(x, y, z);
    }
    if (expected.empty()) continue;
    write_text(dir / "b.pcd", header("x y z rgb", n, "binary") + binary_body(values));
    const RowMatrixX3d p = read_pcd(dir / "b.pcd");
    ASSERT_EQ(p.rows(), Eigen::Index(expected.size())) << "trial " << trial;
    for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_TRUE(p.row(Eigen::Index(i)).isApprox(expected[i]));
  }
}

TEST(PcdReader, ScanSceneAppliesTheFrame) {
  TempDir dir;
  write_text(dir / "s.pcd", header("x y z", 2, "ascii") + "1 0 0\n0 2 0\n");
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  frame.translation() << 10, 0, 1;
  const Scene s = read_scan_scene(dir / "s.pcd", frame);
  EXPECT_TRUE(s.objects.empty());
  ASSERT_EQ(s.points.rows(), 2);
  EXPECT_TRUE(s.points.row(0).isApprox(Eigen::RowVector3d(10, 1, 1), 1e-12)) << s.points.row(0);
  EXPECT_TRUE(s.points.row(1).isApprox(Eigen::RowVector3d(8, 0, 1), 1e-12)) << s.points.row(1);
}

TEST(PcdReader, RejectionsNameTheFile) {
  TempDir dir;
  auto expect_rejected = [&](const std::string& name, const std::string& contents, const std::string& reason) {
    write_text(dir / name, contents);
    const std::string e = error_of([&] { read_pcd(dir / name); });
    EXPECT_THAT(e, HasSubstr(name)) << name;
    EXPECT_THAT(e, HasSubstr(reason)) << name;
  };
  EXPECT_THAT(error_of([&] { read_pcd(dir / "missing.pcd"); }), HasSubstr("missing.pcd: file not found"));
  std::vector<float> ten;
  for (int i = 0; i < 30; ++i) ten.push_back(float(i));
  // Binary data cut short: the header promises 10 points, 5 and a half follow.
  expect_rejected("truncated.pcd", header("x y z", 10, "binary") + binary_body(ten).substr(0, 5 * 12 + 6),
                  "promises 120");
  // ASCII header promising more points than there are lines, or lines short of values.
  expect_rejected("short_ascii.pcd", header("x y z", 5, "ascii") + "1 2 3\n4 5 6\n7 8 9\n", "promises 5");
  expect_rejected("short_line.pcd", header("x y z", 2, "ascii") + "1 2 3\n4 5\n", "point 1");
  expect_rejected("text_numbers.pcd", header("x y z", 2, "ascii") + "1 2 three\n4 5 6\n", "'three' is not a number");
  // WIDTH x HEIGHT disagreeing with POINTS.
  expect_rejected("lying.pcd", header("x y z", 3, "ascii", 7) + "1 2 3\n4 5 6\n7 8 9\n", "WIDTH x HEIGHT");
  expect_rejected("all_nan.pcd", header("x y z", 2, "ascii") + "nan nan nan\nnan 1 2\n", "no finite point");
  expect_rejected("no_xyz.pcd", header("a b c", 1, "ascii") + "1 2 3\n", "no 'x' field");
  expect_rejected("empty_cloud.pcd", header("x y z", 0, "ascii"), "empty");
  // PCL itself crashes on this one: the header check must stop it first.
  expect_rejected("garbage.pcd", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16), "not a PCD file");
  expect_rejected("empty.pcd", "", "not a PCD file");
  expect_rejected("bad_compressed.pcd", header("x y z", 4, "binary_compressed") + std::string(40, '\xff'),
                  "binary_compressed");
  expect_rejected("bad_data.pcd", header("x y z", 1, "zipped") + "1 2 3\n", "zipped");
  expect_rejected("bad_size.pcd", "FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
                  "SIZE");
}

}  // namespace
}  // namespace dmgplace::tools
