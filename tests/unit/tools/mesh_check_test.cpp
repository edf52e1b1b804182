// check_mesh / clean_mesh: topology counts, rejections, and orientation repair on small meshes.
#include "test_support.hpp"
#include "dmgplace/tools/io/mesh_check.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

using ::testing::HasSubstr;

// Unit cube [0,1]^3, faces counter-clockwise seen from outside.
TriMesh cube(double side = 1.0) {
  TriMesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.vertices.row(i) << side * (i & 1), side * ((i >> 1) & 1), side * ((i >> 2) & 1);
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 1, 1, 2, 3,  // z = 0
      4, 5, 6, 5, 7, 6,             // z = 1
      0, 1, 4, 1, 5, 4,             // y = 0
      2, 6, 3, 3, 6, 7,             // y = 1
      0, 4, 2, 2, 4, 6,             // x = 0
      1, 3, 5, 3, 7, 5;             // x = 1
  return m;
}

TriMesh with_faces(const TriMesh& m, const std::vector<Eigen::RowVector3i>& extra) {
  TriMesh out = m;
  out.triangles.conservativeResize(m.triangles.rows() + Eigen::Index(extra.size()), 3);
  for (std::size_t i = 0; i < extra.size(); ++i) out.triangles.row(m.triangles.rows() + Eigen::Index(i)) = extra[i];
  return out;
}

// Every face's normal points away from the center of the (convex) mesh.
bool all_outward(const TriMesh& m) {
  const Eigen::RowVector3d c = m.vertices.colwise().mean();
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    const Eigen::RowVector3d a = m.vertices.row(m.triangles(f, 0)), b = m.vertices.row(m.triangles(f, 1)),
                             d = m.vertices.row(m.triangles(f, 2));
    const Eigen::Vector3d n = (b - a).cross(d - a).transpose();
    if (n.dot(((a + b + d) / 3.0 - c).transpose()) <= 0) return false;
  }
  return true;
}

using ::dmgplace::test::error_of;

bool has_warning(const MeshReport& r, const std::string& text) {
  for (const auto& w : r.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

TEST(MeshCheck, ClosedCubeIsCleanAndHasUnitVolume) {
  const MeshReport r = check_mesh(cube());
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.degenerate_faces, 0u);
  EXPECT_EQ(r.duplicate_faces, 0u);
  EXPECT_TRUE(r.closed_manifold());
  EXPECT_NEAR(signed_volume(cube()), 1.0, 1e-12);
  EXPECT_NEAR(signed_volume(cube(0.1)), 1e-3, 1e-15);
}

TEST(MeshCheck, CountsEdgeUses) {
  // Two triangles walking their shared edge 0->1 the same way: one inconsistent edge, 4 boundary.
  TriMesh m;
  m.vertices.resize(4, 3);
  m.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 0, 1, 3;
  MeshReport r = check_mesh(m);
  EXPECT_EQ(r.inconsistent_edges, 1u);
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_FALSE(r.closed_manifold());
  // A third triangle on edge 0-1 makes it non-manifold (and not "inconsistent").
  m.vertices.conservativeResize(5, 3);
  m.vertices.row(4) << 0, 0, 1;
  m.triangles.conservativeResize(3, 3);
  m.triangles.row(2) << 1, 0, 4;
  r = check_mesh(m);
  EXPECT_EQ(r.nonmanifold_edges, 1u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
}

TEST(MeshCheck, OpenBoxReportsBoundaryEdges) {
  TriMesh box = cube();
  box.triangles.conservativeResize(10, 3);  // drop the x = 1 side: a square hole
  EXPECT_EQ(check_mesh(box).boundary_edges, 4u);
  MeshReport r;
  const TriMesh out = clean_mesh(box, "open_box.stl", r);
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_FALSE(r.closed_manifold());
  EXPECT_FALSE(r.repaired_orientation);
  EXPECT_TRUE(has_warning(r, "open mesh")) << ::testing::PrintToString(r.warnings);
  EXPECT_EQ(out.triangles.rows(), 10);
}

TEST(MeshCheck, FlippedFacesAreRepairedOutward) {
  // Property: whichever faces are flipped (including all of them), the repair restores a
  // consistently outward cube; also after an arbitrary rigid motion.
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    TriMesh m = cube(0.2);
    const Eigen::Quaterniond q = Eigen::Quaterniond::UnitRandom();
    for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
      m.vertices.row(i) = (q * m.vertices.row(i).transpose() + Eigen::Vector3d(0.3, -1.0, 2.0)).transpose();
    int flipped = 0;
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
      if (trial == 0 || rng() % 3 == 0) std::swap(m.triangles(f, 1), m.triangles(f, 2)), ++flipped;
    if (flipped == 0) continue;
    MeshReport r;
    const TriMesh out = clean_mesh(m, "flipped.obj", r);
    EXPECT_TRUE(r.repaired_orientation) << "trial " << trial;
    EXPECT_TRUE(has_warning(r, "repaired orientation")) << "trial " << trial;
    EXPECT_EQ(r.inconsistent_edges, 0u);
    EXPECT_TRUE(r.closed_manifold());
    EXPECT_EQ(check_mesh(out).inconsistent_edges, 0u);
    EXPECT_NEAR(signed_volume(out), 0.008, 1e-9) << "trial " << trial;
    EXPECT_TRUE(all_outward(out)) << "trial " << trial;
    EXPECT_EQ(out.triangles.rows(), 12);
  }
}

TEST(MeshCheck, OpenAndNonManifoldMeshesAreOrientedWithoutCrashing) {
  // An open box with one face turned: consistent again, still open, still outward.
  TriMesh open = cube();
  open.triangles.conservativeResize(10, 3);
  std::swap(open.triangles(2, 1), open.triangles(2, 2));
  MeshReport r;
  TriMesh out = clean_mesh(open, "open.stl", r);
  EXPECT_TRUE(r.repaired_orientation);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_TRUE(all_outward(out));

  // Two cubes sharing one edge (4 faces on it), one face flipped: non-manifold, reported, no crash.
  TriMesh two = cube();
  two.vertices.conservativeResize(14, 3);
  two.triangles.conservativeResize(24, 3);
  // Second cube = first moved by (1, 1, 0); its corners 0 and 4 are the first cube's 3 and 7.
  const int map[8] = {3, 8, 9, 10, 7, 11, 12, 13};
  for (int i = 1; i < 8; ++i)
    if (map[i] >= 8) two.vertices.row(map[i]) = cube().vertices.row(i) + Eigen::RowVector3d(1, 1, 0);
  for (int f = 0; f < 12; ++f)
    for (int j = 0; j < 3; ++j) two.triangles(12 + f, j) = map[cube().triangles(f, j)];
  std::swap(two.triangles(20, 1), two.triangles(20, 2));
  out = clean_mesh(two, "two.stl", r);
  EXPECT_GT(r.nonmanifold_edges + r.boundary_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_NEAR(std::abs(signed_volume(out)), 2.0, 1e-9);
  EXPECT_GT(signed_volume(out), 0);
  EXPECT_FALSE(r.warnings.empty());
}

// `a` and `b` as one mesh; b's faces reversed when `flip_b`.
TriMesh join(const TriMesh& a, const TriMesh& b, bool flip_b) {
  TriMesh m;
  m.vertices.resize(a.vertices.rows() + b.vertices.rows(), 3);
  m.vertices << a.vertices, b.vertices;
  m.triangles.resize(a.triangles.rows() + b.triangles.rows(), 3);
  m.triangles << a.triangles, (b.triangles.array() + int(a.vertices.rows())).matrix();
  if (flip_b)
    for (Eigen::Index f = a.triangles.rows(); f < m.triangles.rows(); ++f)
      std::swap(m.triangles(f, 1), m.triangles(f, 2));
  return m;
}

TEST(MeshCheck, InsideOutPieceBesideAGoodOneIsRepaired) {
  TriMesh far = cube();
  far.vertices.col(0).array() += 3.0;
  const TriMesh two = join(cube(), far, /*flip_b=*/true);  // total volume 0, edges all consistent
  EXPECT_EQ(check_mesh(two).inconsistent_edges, 0u);
  MeshReport r;
  const TriMesh out = clean_mesh(two, "pair.stl", r);
  EXPECT_TRUE(r.repaired_orientation);
  EXPECT_NEAR(signed_volume(out), 2.0, 1e-9);
}

TEST(MeshCheck, HollowBodyKeepsItsInwardInnerShell) {
  TriMesh inner = cube(0.5);
  inner.vertices.array() += 0.25;
  const TriMesh hollow = join(cube(), inner, /*flip_b=*/true);  // the cavity's faces point into it
  MeshReport r;
  const TriMesh out = clean_mesh(hollow, "hollow.stl", r);
  EXPECT_FALSE(r.repaired_orientation) << ::testing::PrintToString(r.warnings);
  EXPECT_NEAR(signed_volume(out), 1.0 - 0.125, 1e-9);
  // And a hollow body whose cavity was written outward is turned the right way.
  const TriMesh wrong = join(cube(), inner, /*flip_b=*/false);
  const TriMesh fixed = clean_mesh(wrong, "hollow.stl", r);
  EXPECT_TRUE(r.repaired_orientation);
  EXPECT_NEAR(signed_volume(fixed), 1.0 - 0.125, 1e-9);
}

TEST(MeshCheck, RepairCanBeTurnedOff) {
  TriMesh m = cube();
  std::swap(m.triangles(0, 1), m.triangles(0, 2));
  MeshReport r;
  clean_mesh(m, "f.stl", r, /*repair=*/false);
  EXPECT_FALSE(r.repaired_orientation);
  EXPECT_EQ(r.inconsistent_edges, 3u);
  EXPECT_TRUE(has_warning(r, "not repaired"));
}

TEST(MeshCheck, MergesDuplicateVerticesOfATriangleSoup) {
  const TriMesh c = cube();
  TriMesh soup;
  soup.vertices.resize(36, 3);
  soup.triangles.resize(12, 3);
  for (int f = 0; f < 12; ++f)
    for (int j = 0; j < 3; ++j) {
      soup.vertices.row(3 * f + j) = c.vertices.row(c.triangles(f, j));
      soup.triangles(f, j) = 3 * f + j;
    }
  EXPECT_EQ(check_mesh(soup).boundary_edges, 36u);
  MeshReport r;
  const TriMesh out = clean_mesh(soup, "soup.stl", r);
  EXPECT_EQ(r.merged_vertices, 28u);
  EXPECT_EQ(out.vertices.rows(), 8);
  EXPECT_TRUE(r.closed_manifold());
  EXPECT_NEAR(signed_volume(out), 1.0, 1e-12);
}

TEST(MeshCheck, DropsDuplicateAndFewDegenerateFaces) {
  // One copy of face 0 as is and one reversed, plus one zero-area face: 1/15 degenerate < 10%.
  TriMesh m = with_faces(cube(), {{0, 2, 1}, {0, 1, 2}, {0, 1, 1}});
  const MeshReport before = check_mesh(m);
  EXPECT_EQ(before.duplicate_faces, 2u);
  EXPECT_EQ(before.degenerate_faces, 1u);
  MeshReport r;
  const TriMesh out = clean_mesh(m, "dups.ply", r);
  EXPECT_EQ(r.duplicate_faces, 2u);
  EXPECT_EQ(r.degenerate_faces, 1u);
  EXPECT_EQ(out.triangles.rows(), 12);
  EXPECT_TRUE(r.closed_manifold());
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_FALSE(r.repaired_orientation);
}

TEST(MeshCheck, CollinearFaceIsDegenerate) {
  TriMesh m = cube();
  m.vertices.conservativeResize(9, 3);
  m.vertices.row(8) << 0.5, 0, 0;  // on the edge 0-1
  m = with_faces(m, {{0, 8, 1}});
  EXPECT_EQ(check_mesh(m).degenerate_faces, 1u);
  MeshReport r;
  EXPECT_EQ(clean_mesh(m, "c.stl", r).triangles.rows(), 12);
  EXPECT_EQ(r.degenerate_faces, 1u);
}

TEST(MeshCheck, RejectionsNameTheFile) {
  MeshReport r;
  EXPECT_THAT(error_of([&] { clean_mesh(TriMesh{}, "empty.stl", r); }), HasSubstr("empty.stl"));
  TriMesh no_faces = cube();
  no_faces.triangles.resize(0, 3);
  EXPECT_THAT(error_of([&] { clean_mesh(no_faces, "nofaces.stl", r); }), HasSubstr("nofaces.stl: mesh: no triangles"));

  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    TriMesh m = cube();
    m.vertices(5, 1) = bad;
    const std::string e = error_of([&] { clean_mesh(m, "nan.obj", r); });
    EXPECT_THAT(e, HasSubstr("nan.obj"));
    EXPECT_THAT(e, HasSubstr("vertex 5"));
  }
  for (int bad : {-1, 8, 1000}) {
    TriMesh m = cube();
    m.triangles(3, 2) = bad;
    const std::string e = error_of([&] { clean_mesh(m, "range.ply", r); });
    EXPECT_THAT(e, HasSubstr("range.ply"));
    EXPECT_THAT(e, HasSubstr("triangle 3"));
    EXPECT_THAT(e, HasSubstr("out of range"));
    EXPECT_THROW(check_mesh(m), Error);
  }
}

TEST(MeshCheck, MostlyDegenerateMeshIsRejected) {
  TriMesh flat;  // every face collinear
  flat.vertices.resize(4, 3);
  flat.vertices << 0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0;
  flat.triangles.resize(2, 3);
  flat.triangles << 0, 1, 2, 1, 2, 3;
  MeshReport r;
  const std::string e = error_of([&] { clean_mesh(flat, "flat.stl", r); });
  EXPECT_THAT(e, HasSubstr("flat.stl"));
  EXPECT_THAT(e, HasSubstr("degenerate"));
  // Just over 10%: 2 of 14 faces.
  EXPECT_THAT(error_of([&] {
                clean_mesh(with_faces(cube(), {{0, 1, 1}, {2, 2, 3}}), "two.stl", r);
              }),
              HasSubstr("2 of 14 faces are degenerate"));
}

TEST(MeshCheck, WarnsAboutImplausibleSizes) {
  MeshReport r;
  clean_mesh(cube(100.0), "mm.stl", r);  // a 100 mm cube written in millimetres
  EXPECT_TRUE(has_warning(r, "--scale 0.001")) << ::testing::PrintToString(r.warnings);
  clean_mesh(cube(0.001), "tiny.stl", r);
  EXPECT_TRUE(has_warning(r, "5 mm")) << ::testing::PrintToString(r.warnings);
  clean_mesh(cube(0.1), "ok.stl", r);
  EXPECT_TRUE(r.warnings.empty()) << ::testing::PrintToString(r.warnings);
}

}  // namespace
}  // namespace dmgplace::tools
