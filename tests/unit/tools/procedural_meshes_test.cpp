// Property tests of the built-in procedural meshes and of the STL / OBJ writers.
#include "dmgplace/tools/geometry/procedural_meshes.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "dmgplace/formats/error.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

namespace fs = std::filesystem;
using test::TempDir;
using ::testing::AssertionFailure;
using ::testing::AssertionResult;
using ::testing::AssertionSuccess;

Eigen::Vector3d vertex(const TriMesh& m, int i) { return m.vertices.row(i).transpose(); }

// Every undirected edge is used by exactly two triangles, once in each direction. Together with
// a positive volume this means closed and consistently oriented outwards.
AssertionResult closed_and_oriented(const TriMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) ++directed[{m.triangles(t, k), m.triangles(t, (k + 1) % 3)}];
  for (const auto& [e, count] : directed) {
    if (count != 1)
      return AssertionFailure() << "directed edge " << e.first << "->" << e.second << " used " << count << " times";
    if (!directed.contains({e.second, e.first}))
      return AssertionFailure() << "edge " << e.first << "-" << e.second << " has one triangle only";
  }
  // A closed orientable surface of genus 0: V - E + F = 2.
  const auto v = m.vertices.rows(), e = static_cast<Eigen::Index>(directed.size() / 2), f = m.triangles.rows();
  if (v - e + f != 2) return AssertionFailure() << "Euler characteristic " << v - e + f << ", want 2";
  return AssertionSuccess();
}

// Around every vertex the triangles form one closed fan: no pinched or unused vertices.
AssertionResult manifold_vertices(const TriMesh& m) {
  std::vector<std::map<int, int>> fan(static_cast<std::size_t>(m.vertices.rows()));
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = m.triangles(t, k), a = m.triangles(t, (k + 1) % 3), b = m.triangles(t, (k + 2) % 3);
      if (!fan[std::size_t(v)].emplace(a, b).second)
        return AssertionFailure() << "vertex " << v << ": two triangles leave through the same edge";
    }
  }
  for (std::size_t v = 0; v < fan.size(); ++v) {
    const auto& next = fan[v];
    if (next.empty()) return AssertionFailure() << "vertex " << v << " is not used";
    int cur = next.begin()->first;
    std::size_t steps = 0;
    do {
      const auto it = next.find(cur);
      if (it == next.end()) return AssertionFailure() << "vertex " << v << ": fan is open";
      cur = it->second;
      ++steps;
    } while (cur != next.begin()->first && steps <= next.size());
    if (steps != next.size())
      return AssertionFailure() << "vertex " << v << ": " << next.size() << " triangles but a fan of " << steps;
  }
  return AssertionSuccess();
}

AssertionResult no_duplicate_vertices(const TriMesh& m) {
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    for (Eigen::Index j = i + 1; j < m.vertices.rows(); ++j)
      if ((m.vertices.row(i) - m.vertices.row(j)).norm() < 1e-9)
        return AssertionFailure() << "vertices " << i << " and " << j << " coincide";
  return AssertionSuccess();
}

AssertionResult no_degenerate_triangles(const TriMesh& m) {
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const int a = m.triangles(t, 0), b = m.triangles(t, 1), c = m.triangles(t, 2);
    if (a == b || b == c || a == c) return AssertionFailure() << "triangle " << t << " repeats a vertex";
    const double area = 0.5 * (vertex(m, b) - vertex(m, a)).cross(vertex(m, c) - vertex(m, a)).norm();
    if (area < 1e-10) return AssertionFailure() << "triangle " << t << " has area " << area;
  }
  return AssertionSuccess();
}

double signed_volume(const TriMesh& m) {
  double six_v = 0;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t)
    six_v += vertex(m, m.triangles(t, 0)).dot(vertex(m, m.triangles(t, 1)).cross(vertex(m, m.triangles(t, 2))));
  return six_v / 6;
}

void expect_valid_solid(const TriMesh& m) {
  EXPECT_TRUE(closed_and_oriented(m));
  EXPECT_TRUE(manifold_vertices(m));
  EXPECT_TRUE(no_duplicate_vertices(m));
  EXPECT_TRUE(no_degenerate_triangles(m));
  EXPECT_GT(signed_volume(m), 0) << "triangles face inwards";
}

// Area of a regular n-gon inscribed in the circle of radius r.
double polygon_area(int n, double r) { return 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n); }

using ::dmgplace::test::error_of;

TEST(ProceduralMeshChecks, CatchBrokenMeshes) {
  const TriMesh good = make_box_mesh(Eigen::Vector3d(1, 2, 3));
  ASSERT_TRUE(closed_and_oriented(good));
  ASSERT_TRUE(manifold_vertices(good));

  TriMesh flipped = good;  // one triangle wound the wrong way
  std::swap(flipped.triangles(5, 1), flipped.triangles(5, 2));
  EXPECT_FALSE(closed_and_oriented(flipped));

  TriMesh open = good;  // a hole
  open.triangles.conservativeResize(11, 3);
  EXPECT_FALSE(closed_and_oriented(open));

  TriMesh inside_out = good;
  inside_out.triangles.col(1).swap(inside_out.triangles.col(2));
  EXPECT_TRUE(closed_and_oriented(inside_out));
  EXPECT_LT(signed_volume(inside_out), 0);

  TriMesh duplicated = good;  // vertex 7 twice, the copy used by one triangle
  duplicated.vertices.conservativeResize(9, 3);
  duplicated.vertices.row(8) = duplicated.vertices.row(7);
  for (int k = 0; k < 3; ++k)
    if (duplicated.triangles(3, k) == 7) duplicated.triangles(3, k) = 8;
  EXPECT_FALSE(no_duplicate_vertices(duplicated));
  EXPECT_FALSE(closed_and_oriented(duplicated));

  TriMesh degenerate = good;  // squash the +z face into the -z plane
  for (int i = 4; i < 8; ++i) degenerate.vertices(i, 2) = degenerate.vertices(0, 2);
  EXPECT_FALSE(no_degenerate_triangles(degenerate));
  TriMesh repeated = good;
  repeated.triangles(0, 1) = repeated.triangles(0, 0);
  EXPECT_FALSE(no_degenerate_triangles(repeated));

  // Two tetrahedra sharing only vertex 0: every edge is fine, the vertex is pinched.
  TriMesh pinched;
  pinched.vertices.resize(7, 3);
  pinched.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1;
  pinched.triangles.resize(8, 3);
  pinched.triangles << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3,  //
      0, 4, 5, 0, 6, 4, 0, 5, 6, 4, 6, 5;
  EXPECT_FALSE(manifold_vertices(pinched));
}

TEST(ProceduralMeshes, BoxIsAClosedSolidOfExactVolume) {
  const Eigen::Vector3d e(0.3, 0.2, 0.1);
  const TriMesh m = make_box_mesh(e);
  EXPECT_EQ(m.vertices.rows(), 8);
  EXPECT_EQ(m.triangles.rows(), 12);
  expect_valid_solid(m);
  EXPECT_NEAR(signed_volume(m), e.prod(), 1e-15);
  EXPECT_TRUE(m.vertices.colwise().maxCoeff().transpose().isApprox(e / 2));
  EXPECT_TRUE(m.vertices.colwise().minCoeff().transpose().isApprox(-e / 2));
}

TEST(ProceduralMeshes, EraserIsABoardEraserSizedBox) {
  const TriMesh m = make_eraser_mesh();
  expect_valid_solid(m);
  const Eigen::Vector3d lo = m.vertices.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = m.vertices.colwise().maxCoeff().transpose();
  EXPECT_TRUE((hi - lo).isApprox(Eigen::Vector3d(0.13, 0.05, 0.035)));
  EXPECT_TRUE((hi + lo).isZero(1e-15)) << "centered at the origin";
  EXPECT_NEAR(signed_volume(m), 0.13 * 0.05 * 0.035, 1e-15);
}

TEST(ProceduralMeshes, CylinderVolumeIsThePolygonPrism) {
  const double r = 0.04, h = 0.15;
  for (int n : {3, 4, 7, 32, 200}) {
    SCOPED_TRACE("segments " + std::to_string(n));
    const TriMesh m = make_cylinder_mesh(r, h, n);
    expect_valid_solid(m);
    EXPECT_NEAR(signed_volume(m), polygon_area(n, r) * h, 1e-15);
    EXPECT_DOUBLE_EQ(m.vertices.col(2).minCoeff(), 0.0);
    EXPECT_DOUBLE_EQ(m.vertices.col(2).maxCoeff(), h);
    for (Eigen::Index i = 0; i < m.vertices.rows(); ++i) {
      const double rho = m.vertices.row(i).head<2>().norm();
      EXPECT_TRUE(rho < 1e-15 || std::abs(rho - r) < 1e-15) << "vertex " << i << " at radius " << rho;
    }
  }
  // Fine tessellation approaches the circular cylinder.
  EXPECT_NEAR(signed_volume(make_cylinder_mesh(r, h, 200)), std::numbers::pi * r * r * h,
              1e-3 * std::numbers::pi * r * r * h);
}

TEST(ProceduralMeshes, BottleIsAClosedSolidOfRevolution) {
  const BottleShape s;
  const TriMesh m = make_bottle_mesh();
  expect_valid_solid(m);
  const double pi = std::numbers::pi;
  const double R = s.body_radius, rc = s.cap_radius;
  const double analytic = pi * R * R * s.body_height + pi * s.shoulder_height / 3 * (R * R + R * rc + rc * rc) +
                          pi * rc * rc * s.cap_height;
  const double v = signed_volume(m);
  EXPECT_NEAR(v, analytic, 0.02 * analytic);
  // Every cross-section is a regular polygon inscribed in the circle, so the ratio is exact.
  EXPECT_NEAR(v, analytic * polygon_area(s.segments, 1) / pi, 1e-12 * analytic);
  // Flat bottom at z = 0, cap on top, nothing wider than the body.
  const double top = s.body_height + s.shoulder_height + s.cap_height;
  EXPECT_DOUBLE_EQ(m.vertices.col(2).minCoeff(), 0.0);
  EXPECT_NEAR(m.vertices.col(2).maxCoeff(), top, 1e-15);
  double widest = 0, widest_at_top = 0;
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i) {
    const double rho = m.vertices.row(i).head<2>().norm();
    widest = std::max(widest, rho);
    if (std::abs(m.vertices(i, 2) - top) < 1e-12) widest_at_top = std::max(widest_at_top, rho);
  }
  EXPECT_NEAR(widest, R, 1e-15);
  EXPECT_NEAR(widest_at_top, rc, 1e-15);
}

TEST(ProceduralMeshes, BottleVariantsStayValid) {
  BottleShape flat_step;  // no shoulder: the body top is an annulus
  flat_step.shoulder_height = 0;
  BottleShape coarse;
  coarse.segments = 3;
  BottleShape tall;
  tall.body_radius = 0.05;
  tall.body_height = 0.3;
  tall.shoulder_height = 0.06;
  tall.cap_radius = 0.049;
  tall.cap_height = 0.01;
  tall.segments = 64;
  for (const BottleShape& s : {flat_step, coarse, tall}) {
    SCOPED_TRACE("segments " + std::to_string(s.segments) + ", shoulder " + std::to_string(s.shoulder_height));
    const TriMesh m = make_bottle_mesh(s);
    expect_valid_solid(m);
    const double k = polygon_area(s.segments, 1);
    const double R = s.body_radius, rc = s.cap_radius;
    const double expected =
        k * (R * R * s.body_height + s.shoulder_height / 3 * (R * R + R * rc + rc * rc) + rc * rc * s.cap_height);
    EXPECT_NEAR(signed_volume(m), expected, 1e-12 * expected);
  }
}

TEST(ProceduralMeshes, RejectInvalidParameters) {
  EXPECT_THROW(make_box_mesh(Eigen::Vector3d(0.1, 0, 0.1)), Error);
  EXPECT_THROW(make_box_mesh(Eigen::Vector3d(0.1, -0.1, 0.1)), Error);
  EXPECT_THROW(make_box_mesh(Eigen::Vector3d(0.1, std::nan(""), 0.1)), Error);
  EXPECT_THROW(make_cylinder_mesh(0.1, 0.1, 2), Error);
  EXPECT_THROW(make_cylinder_mesh(0, 0.1, 8), Error);
  EXPECT_THROW(make_cylinder_mesh(0.1, -1, 8), Error);
  BottleShape s;
  s.cap_radius = s.body_radius;
  EXPECT_THROW(make_bottle_mesh(s), Error);
  s = {};
  s.shoulder_height = -0.01;
  EXPECT_THROW(make_bottle_mesh(s), Error);
  s = {};
  s.segments = 2;
  EXPECT_THROW(make_bottle_mesh(s), Error);
  s = {};
  s.cap_height = 0;
  EXPECT_THROW(make_bottle_mesh(s), Error);
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::uint32_t get_u32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(static_cast<unsigned char>(b[at + std::size_t(i)])) << (8 * i);
  return v;
}
float get_f32(const std::string& b, std::size_t at) { return std::bit_cast<float>(get_u32(b, at)); }

TEST(ProceduralStl, WritesBinaryStlThatReadsBack) {
  TempDir dir;
  const TriMesh m = make_bottle_mesh();
  const fs::path p = dir / "bottle.stl";
  write_stl_binary(m, p);
  const std::string b = read_bytes(p);
  const std::size_t n = std::size_t(m.triangles.rows());
  ASSERT_EQ(b.size(), 84 + 50 * n);
  EXPECT_NE(b.substr(0, 5), "solid") << "would be taken for ASCII STL";
  ASSERT_EQ(get_u32(b, 80), n);
  for (std::size_t t = 0; t < n; ++t) {
    const std::size_t at = 84 + 50 * t;
    Eigen::Vector3d corner[3];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) {
        const float f = get_f32(b, at + 12 + 12 * std::size_t(k) + 4 * std::size_t(c));
        ASSERT_EQ(f, static_cast<float>(m.vertices(m.triangles(Eigen::Index(t), k), c))) << "triangle " << t;
        corner[k][c] = f;
      }
    }
    const Eigen::Vector3d normal(get_f32(b, at), get_f32(b, at + 4), get_f32(b, at + 8));
    const Eigen::Vector3d face = (corner[1] - corner[0]).cross(corner[2] - corner[0]).normalized();
    EXPECT_NEAR(normal.norm(), 1.0, 1e-6) << "triangle " << t;
    EXPECT_GT(normal.dot(face), 0.999) << "triangle " << t;
    EXPECT_EQ(b[at + 48], '\0');
    EXPECT_EQ(b[at + 49], '\0');
  }
}

TEST(ProceduralStl, ErrorsNameTheFile) {
  TempDir dir;
  const std::string msg = error_of([&] { write_stl_binary(make_eraser_mesh(), dir / "no_such_dir" / "eraser.stl"); });
  EXPECT_NE(msg.find("eraser.stl"), std::string::npos) << msg;
  TriMesh bad = make_eraser_mesh();
  bad.triangles(4, 2) = 8;
  const std::string idx = error_of([&] { write_stl_binary(bad, dir / "bad.stl"); });
  EXPECT_NE(idx.find("bad.stl"), std::string::npos) << idx;
  EXPECT_NE(idx.find("out of range"), std::string::npos) << idx;
  const std::string obj = error_of([&] { write_obj(bad, dir / "bad.obj"); });
  EXPECT_NE(obj.find("bad.obj"), std::string::npos) << obj;
}

TEST(ProceduralObj, WritesVerticesAndFacesThatReadBack) {
  TempDir dir;
  const TriMesh m = make_bottle_mesh();
  write_obj(m, dir / "bottle.obj");
  std::istringstream in(read_bytes(dir / "bottle.obj"));
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      Eigen::Vector3d p;
      ls >> p.x() >> p.y() >> p.z();
      ASSERT_TRUE(ls) << line;
      v.push_back(p);
    } else if (tag == "f") {
      Eigen::Vector3i t;
      ls >> t.x() >> t.y() >> t.z();
      ASSERT_TRUE(ls) << line;
      f.push_back(t - Eigen::Vector3i::Ones());
    }
  }
  ASSERT_EQ(Eigen::Index(v.size()), m.vertices.rows());
  ASSERT_EQ(Eigen::Index(f.size()), m.triangles.rows());
  for (std::size_t i = 0; i < v.size(); ++i)
    EXPECT_EQ(v[i], Eigen::Vector3d(m.vertices.row(Eigen::Index(i)))) << "vertex " << i << " must round-trip exactly";
  for (std::size_t i = 0; i < f.size(); ++i) EXPECT_EQ(f[i], Eigen::Vector3i(m.triangles.row(Eigen::Index(i))));
}

}  // namespace
}  // namespace dmgplace::tools
