// Reproducers from fuzzing the readers (scripts/fuzz, docs/reliability.md): each input once made a
// reader crash, abort or allocate without bound; now each must be a clean dmgplace::Error.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/io/pcd_reader.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

using test::error_of;
using test::TempDir;
using test::write_text;
using ::testing::HasSubstr;

std::string le32(std::uint32_t v) {
  std::string s(4, '\0');
  for (int i = 0; i < 4; ++i) s[std::size_t(i)] = char((v >> (8 * i)) & 0xff);
  return s;
}

// POINTS x point size = 2^31 x (3 x 8 x 2^31) wraps to 0 in 64 bits: the size check passed and PCL
// asked for a 0x7ffffff400000000-byte buffer (ASan: allocation-size-too-big).
TEST(FuzzRegression, PcdHeaderSizeProductOverflows) {
  TempDir dir;
  write_text(dir / "o.pcd",
             "VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 2147483648 2147483648 2147483648\n"
             "WIDTH 2147483648\nHEIGHT 1\nPOINTS 2147483648\nDATA binary\n0123456789abcdef");
  EXPECT_THAT(error_of([&] { read_pcd(dir / "o.pcd"); }), HasSubstr("overflows"));
}

// binary_compressed claiming 3.6 GB from a 10-byte LZF block: PCL allocated the claimed size
// before decompressing (7 GB resident in a release build; libFuzzer: out-of-memory).
TEST(FuzzRegression, PcdCompressedSizeBeyondLzfRatio) {
  TempDir dir;
  write_text(dir / "c.pcd",
             "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 300000000\nHEIGHT 1\n"
             "POINTS 300000000\nDATA binary_compressed\n" +
                 le32(10) + le32(3600000000u) + std::string(1, '\x08') + "012345678");
  EXPECT_THAT(error_of([&] { read_pcd(dir / "c.pcd"); }), HasSubstr("88:1"));
}

// fuzz_mesh_reader timeout: assimp's PLY importer read past the end forever when the header had no
// end_header line (`dmgplace bake-env` hung). It picks PLY by content, so other extensions too.
TEST(FuzzRegression, PlyHeaderWithoutEndHeaderIsRejectedNotHung) {
  TempDir dir;
  const std::string fuzzed =
      "ply\nformat ascii 1.0\ncomment tetrahedrle\nnoement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int ";
  const std::string minimal = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n";
  write_text(dir / "fuzzed.ply", fuzzed);
  write_text(dir / "minimal.ply", minimal);
  write_text(dir / "no_extension", minimal);
  write_text(dir / "in_comment.PLY", minimal + "comment end_header\n");
  // Second fuzz run: end_header glued to a control character (assimp missed it and looped again).
  write_text(dir / "glued.ply",
             minimal + "element face 1\nproperty list uchar int vertex_indices\nend_header\b0 0 0\n");
  write_text(dir / "control.ply", "ply\nformat ascii 1.0\nelement vertex 4\x13property float x\nend_header\n");
  for (const char* name : {"fuzzed.ply", "minimal.ply", "no_extension", "in_comment.PLY"})
    EXPECT_THAT(error_of([&] { read_mesh(dir / name); }), HasSubstr("PLY header has no end_header")) << name;
  for (const char* name : {"glued.ply", "control.ply"})
    EXPECT_THAT(error_of([&] { read_mesh(dir / name); }), HasSubstr("control character in the PLY header")) << name;
  // A complete header still goes through (then fails for its own reason: no faces).
  write_text(dir / "ok.ply", minimal + "end_header\n1\n2\n3\n4\n");
  EXPECT_THAT(error_of([&] { read_mesh(dir / "ok.ply"); }), ::testing::Not(HasSubstr("end_header")));
}

// fuzz_mesh_reader crashes in assimp's post-processing. Binary PLY whose first face points at vertex
// 0x4f4f4f4f of 4: SEGV in JoinIdenticalVertices. ASCII PLY whose body is one short line: the mesh
// is flagged as holding polygons without any, and Triangulate aborted on its ai_assert (also in a
// release build: `dmgplace bake-env` died with SIGABRT).
TEST(FuzzRegression, PlyFilesThatCrashedAssimpAreRejected) {
  TempDir dir;
  const std::string header =
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
      "property list uchar int vertex_indices\nend_header\n";
  std::string body;
  const auto f32 = [&](float v) { body.append(reinterpret_cast<const char*>(&v), 4); };
  const auto face = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    body += '\x03';
    body += le32(a) + le32(b) + le32(c);
  };
  for (const float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f}) f32(v);
  face(0x4f4f4f4f, 0x4f4f4f4f, 0x4f4f4f4f);
  face(0, 1, 3), face(0, 3, 2), face(1, 2, 3);
  write_text(dir / "index.ply", "ply\nformat binary_little_endian 1.0\n" + header + body);
  write_text(dir / "short.ply", "ply\nformat ascii 1.0\ncomment tetrahedron\n" + header + "0  1 2 3\n");
  EXPECT_THAT(error_of([&] { read_mesh(dir / "index.ply"); }), HasSubstr("cannot read mesh"));
  EXPECT_THAT(error_of([&] { read_mesh(dir / "short.ply"); }), HasSubstr("short.ply"));
}

// fuzz_urdf_reader leaks: a joint whose parent is its own child, or a longer joint cycle. urdfdom
// leaked the cycle's links (shared_ptr cycle) and, when it still found one root, accepted the file
// with every link of the cycle and below dropped silently (a robot or scene missing links).
TEST(FuzzRegression, UrdfJointCyclesAreRejected) {
  TempDir dir;
  const std::string links = "<link name=\"base\"/><link name=\"arm\"/><link name=\"tip\"/>";
  const auto joint = [](const char* name, const char* parent, const char* child) {
    return std::string("<joint name=\"") + name + "\" type=\"fixed\"><parent link=\"" + parent + "\"/><child link=\"" +
           child + "\"/></joint>";
  };
  write_text(dir / "self.urdf",
             "<robot name=\"r\">" + links + joint("j1", "arm", "arm") + joint("j2", "arm", "tip") + "</robot>");
  write_text(dir / "loop.urdf",
             "<robot name=\"r\">" + links + joint("j1", "arm", "tip") + joint("j2", "tip", "arm") + "</robot>");
  write_text(dir / "two_parents.urdf", "<robot name=\"r\">" + links + joint("j1", "base", "arm") +
                                           joint("j2", "base", "tip") + joint("j3", "tip", "arm") + "</robot>");
  EXPECT_THAT(error_of([&] { read_urdf(dir / "self.urdf"); }), HasSubstr("link 'arm': is its own ancestor"));
  EXPECT_THAT(error_of([&] { read_urdf(dir / "loop.urdf"); }), HasSubstr("joint cycle"));
  EXPECT_THAT(error_of([&] { read_urdf_scene(dir / "loop.urdf"); }), HasSubstr("joint cycle"));
  EXPECT_THAT(error_of([&] { read_urdf(dir / "two_parents.urdf"); }), HasSubstr("child of more than one joint"));
  // A tree still reads.
  write_text(dir / "tree.urdf",
             "<robot name=\"r\">" + links + joint("j1", "base", "arm") + joint("j2", "arm", "tip") + "</robot>");
  EXPECT_EQ(read_urdf(dir / "tree.urdf").links.size(), 3u);
}

}  // namespace
}  // namespace dmgplace::tools
