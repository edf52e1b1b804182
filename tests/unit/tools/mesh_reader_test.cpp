// read_mesh: small STL (ascii + binary), OBJ, PLY and DAE files written here, scale, rejections.
#include "dmgplace/tools/io/mesh_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <sstream>

#include "dmgplace/formats/error.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

using test::TempDir;
using test::write_text;
using ::testing::HasSubstr;

// Unit cube corners and outward counter-clockwise faces.
const double kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
const int kFace[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                          {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};

std::string cube_ascii_stl(double s) {
  std::ostringstream o;
  o << "solid cube\n";
  for (const auto& f : kFace) {
    o << " facet normal 0 0 0\n  outer loop\n";
    for (int v : f)
      o << "   vertex " << s * kCorner[v][0] << " " << s * kCorner[v][1] << " " << s * kCorner[v][2] << "\n";
    o << "  endloop\n endfacet\n";
  }
  o << "endsolid cube\n";
  return o.str();
}

std::string cube_binary_stl(double s, int faces = 12) {
  std::string b(80, ' ');
  b.replace(0, 12, "binary cube ");
  const std::uint32_t n = 12;
  b.append(reinterpret_cast<const char*>(&n), 4);
  for (int f = 0; f < faces; ++f) {
    float rec[12] = {0, 0, 0};
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) rec[3 + 3 * j + k] = float(s * kCorner[kFace[f][j]][k]);
    b.append(reinterpret_cast<const char*>(rec), sizeof rec);
    b.append(2, '\0');
  }
  return b;
}

std::string cube_obj(double s, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero(), int base = 1) {
  std::ostringstream o;
  for (const auto& c : kCorner)
    o << "v " << s * c[0] + offset.x() << " " << s * c[1] + offset.y() << " " << s * c[2] + offset.z() << "\n";
  for (const auto& f : kFace) o << "f " << f[0] + base << " " << f[1] + base << " " << f[2] + base << "\n";
  return o.str();
}

std::string cube_ply(double s) {
  std::ostringstream o;
  o << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& c : kCorner) o << s * c[0] << " " << s * c[1] << " " << s * c[2] << "\n";
  for (const auto& f : kFace) o << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
  return o.str();
}

// A Collada cube under a node translated by (1, 2, 3), declared z-up in centimetres.
std::string cube_dae() {
  std::ostringstream pos, idx;
  for (const auto& c : kCorner) pos << c[0] << " " << c[1] << " " << c[2] << " ";
  for (const auto& f : kFace) idx << f[0] << " " << f[1] << " " << f[2] << " ";
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="cube" name="cube"><mesh>
    <source id="cube-pos"><float_array id="cube-pos-array" count="24">)" +
         pos.str() + R"(</float_array>
      <technique_common><accessor source="#cube-pos-array" count="8" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="cube-vtx"><input semantic="POSITION" source="#cube-pos"/></vertices>
    <triangles count="12"><input semantic="VERTEX" source="#cube-vtx" offset="0"/><p>)" +
         idx.str() + R"(</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene">
    <node id="n" name="n"><translate>1 2 3</translate><instance_geometry url="#cube"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

using ::dmgplace::test::error_of;

Eigen::RowVector3d extent(const TriMesh& m) {
  return m.vertices.colwise().maxCoeff() - m.vertices.colwise().minCoeff();
}

struct Case {
  const char* name;
  std::string (*text)(double);
};

TEST(MeshReader, RoundTripsEveryFormatAtEveryScale) {
  const Case cases[] = {{"cube.stl", cube_ascii_stl},
                        {"cube_bin.stl", [](double s) { return cube_binary_stl(s); }},
                        {"cube.obj", [](double s) { return cube_obj(s); }},
                        {"cube.ply", cube_ply}};
  TempDir dir;
  for (const auto& c : cases)
    for (double side : {0.05, 0.3, 1.0})
      for (double scale : {1.0, 0.5, 2.0}) {
        write_text(dir / c.name, c.text(side));
        MeshReport r;
        MeshReadOptions opt;
        opt.scale = scale;
        const TriMesh m = read_mesh(dir / c.name, opt, &r);
        SCOPED_TRACE(std::string(c.name) + " side " + std::to_string(side) + " scale " + std::to_string(scale));
        EXPECT_EQ(m.vertices.rows(), 8);
        EXPECT_EQ(m.triangles.rows(), 12);
        EXPECT_TRUE(r.closed_manifold());
        EXPECT_EQ(r.inconsistent_edges, 0u);
        EXPECT_FALSE(r.repaired_orientation);
        const double s = side * scale;
        EXPECT_NEAR(signed_volume(m), s * s * s, 1e-6 * s * s * s);
        EXPECT_TRUE(extent(m).isApprox(Eigen::RowVector3d::Constant(s), 1e-6));
        EXPECT_NEAR(m.vertices.minCoeff(), 0.0, 1e-9);
      }
}

TEST(MeshReader, ScaleMillimetresToMetres) {
  TempDir dir;
  write_text(dir / "mm.stl", cube_ascii_stl(120.0));  // a 120 mm cube written in millimetres
  MeshReport r;
  read_mesh(dir / "mm.stl", {}, &r);
  EXPECT_THAT(::testing::PrintToString(r.warnings), HasSubstr("--scale 0.001"));
  MeshReadOptions mm;
  mm.scale = 0.001;
  const TriMesh m = read_mesh(dir / "mm.stl", mm, &r);
  EXPECT_TRUE(extent(m).isApprox(Eigen::RowVector3d::Constant(0.12), 1e-6));
  EXPECT_TRUE(r.warnings.empty()) << ::testing::PrintToString(r.warnings);
}

TEST(MeshReader, MirroringAxisScaleKeepsFacesOutward) {
  TempDir dir;
  write_text(dir / "c.obj", cube_obj(1.0));
  MeshReadOptions opt;
  opt.axis_scale = Eigen::Vector3d(-1, 2, 1);
  MeshReport r;
  const TriMesh m = read_mesh(dir / "c.obj", opt, &r);
  EXPECT_NEAR(signed_volume(m), 2.0, 1e-9);
  EXPECT_FALSE(r.repaired_orientation);  // the winding was swapped with the mirror, not repaired later
  EXPECT_NEAR(m.vertices.col(0).minCoeff(), -1.0, 1e-9);
}

TEST(MeshReader, MergesAllObjectsOfAFile) {
  TempDir dir;
  write_text(dir / "two.obj", "o first\n" + cube_obj(1.0) + "o second\n" + cube_obj(1.0, {3, 0, 0}, 9));
  MeshReport r;
  const TriMesh m = read_mesh(dir / "two.obj", {}, &r);
  EXPECT_EQ(m.triangles.rows(), 24);
  EXPECT_EQ(m.vertices.rows(), 16);
  EXPECT_TRUE(r.closed_manifold());
  EXPECT_NEAR(signed_volume(m), 2.0, 1e-9);
  EXPECT_NEAR(m.vertices.col(0).maxCoeff(), 4.0, 1e-9);
}

TEST(MeshReader, ColladaNodeTransformAndUnitApplyButAxesStay) {
  TempDir dir;
  write_text(dir / "cube.dae", cube_dae());
  const TriMesh m = read_mesh(dir / "cube.dae");
  // centimetres: the 1-unit cube is 1 cm, translated by (1, 2, 3) cm, z-up kept as is.
  EXPECT_TRUE(m.vertices.colwise().minCoeff().isApprox(Eigen::RowVector3d(0.01, 0.02, 0.03), 1e-6))
      << m.vertices.colwise().minCoeff();
  EXPECT_TRUE(extent(m).isApprox(Eigen::RowVector3d::Constant(0.01), 1e-6));
  EXPECT_NEAR(signed_volume(m), 1e-6, 1e-12);
}

TEST(MeshReader, FlippedFacesInAFileAreRepaired) {
  TempDir dir;
  std::string obj = cube_obj(1.0);
  obj.replace(obj.find("f 1 3 2"), 7, "f 1 2 3");  // first face turned inwards
  write_text(dir / "flip.obj", obj);
  MeshReport r;
  const TriMesh m = read_mesh(dir / "flip.obj", {}, &r);
  EXPECT_TRUE(r.repaired_orientation);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_NEAR(signed_volume(m), 1.0, 1e-9);
}

TEST(MeshReader, RejectionsNameTheFile) {
  TempDir dir;
  auto expect_rejected = [&](const std::string& name, const std::string& contents, const std::string& reason) {
    write_text(dir / name, contents);
    const std::string e = error_of([&] { read_mesh(dir / name); });
    EXPECT_THAT(e, HasSubstr(name)) << name;
    EXPECT_THAT(e, HasSubstr(reason)) << name;
  };
  EXPECT_THAT(error_of([&] { read_mesh(dir / "missing.stl"); }), HasSubstr("missing.stl: file not found"));
  std::string garbage;
  for (int i = 0; i < 997; ++i) garbage += char((i * 7919) % 251);
  expect_rejected("garbage.stl", garbage, "cannot read mesh");
  expect_rejected("garbage.obj", garbage, "no triangles");  // assimp "reads" it: nothing but junk lines
  expect_rejected("garbage.ply", garbage, "cannot read mesh");
  expect_rejected("garbage.dae", garbage, "cannot read mesh");
  expect_rejected("empty.stl", "", "cannot read mesh");
  expect_rejected("empty.obj", "# nothing here\n", "cannot read mesh");
  expect_rejected("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no triangles");
  expect_rejected("truncated.stl", cube_binary_stl(1.0, 7), "cannot read mesh");  // header says 12 faces, 7 follow
  expect_rejected("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n", "NaN");
  expect_rejected("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "out of range");
  expect_rejected("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n", "degenerate");
  // Scale must be a usable number.
  write_text(dir / "ok.obj", cube_obj(1.0));
  MeshReadOptions zero;
  zero.scale = 0;
  EXPECT_THAT(error_of([&] { read_mesh(dir / "ok.obj", zero); }), HasSubstr("ok.obj: scale"));
  EXPECT_THAT(error_of([&] { read_mesh(dir.path()); }), HasSubstr("not a regular file"));
}

}  // namespace
}  // namespace dmgplace::tools
