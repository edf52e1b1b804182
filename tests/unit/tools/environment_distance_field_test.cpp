// Distance and clearance grids from Embree against brute force and the analytic SDF.
#include <gtest/gtest.h>

#include <random>

#include "analytic_sdf.hpp"
#include "dmgplace/runtime/environment/environment_model.hpp"
#include "dmgplace/tools/environment/closest_point.hpp"
#include "dmgplace/tools/environment/distance_field.hpp"

using namespace dmgplace;
using namespace dmgplace::tools;

namespace {

Shape prim(ShapeType t, Eigen::Vector3d size, Eigen::Vector3d at, double yaw = 0) {
  Shape s;
  s.type = t;
  s.size = size;
  s.origin.translation() = at;
  s.origin.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return s;
}

// Overlapping primitives of all kinds (a box through a sphere, a rotated box, a cylinder).
Scene primitive_scene() {
  Scene s;
  s.objects.push_back({"floor", {prim(ShapeType::Box, {1.2, 1.2, 0.04}, {0, 0, -0.02})}});
  s.objects.push_back({"crate", {prim(ShapeType::Box, {0.2, 0.3, 0.25}, {0.1, -0.1, 0.125}, 0.4)}});
  s.objects.push_back({"ball", {prim(ShapeType::Sphere, {0.12, 0, 0}, {0.15, -0.05, 0.3})}});
  s.objects.push_back({"can", {prim(ShapeType::Cylinder, {0.05, 0.3, 0}, {-0.25, 0.2, 0.15})}});
  return s;
}

double brute_force(const EnvironmentGeometry& g, const Eigen::Vector3d& p) {
  double best = INFINITY;
  for (const auto& m : g.meshes)
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t)
      best = std::min(best, squared_distance_to_triangle(p, m.vertices.row(m.triangles(t, 0)).transpose(),
                                                         m.vertices.row(m.triangles(t, 1)).transpose(),
                                                         m.vertices.row(m.triangles(t, 2)).transpose()));
  for (Eigen::Index i = 0; i < g.points.rows(); ++i)
    best = std::min(best, (g.points.row(i).transpose() - p).squaredNorm());
  return std::sqrt(best);
}

const Eigen::AlignedBox3d kBox(Eigen::Vector3d(-0.45, -0.45, -0.1), Eigen::Vector3d(0.45, 0.45, 0.5));
constexpr double kRes = 0.02, kBand = 0.12;

}  // namespace

TEST(EnvDistanceField, GridSamplesEqualBruteForceDistanceWithSign) {
  const Scene scene = primitive_scene();
  const EnvironmentGeometry geo = make_environment_geometry(scene, 48);
  const EmbreeScene embree(geo);
  const GridSpec spec = grid_covering(kBox, kRes);
  const auto f = distance_field(embree, spec, kBand, 2);
  ASSERT_EQ(f.values.size(), spec.size());
  std::mt19937 rng(7);
  int checked = 0, negative = 0;
  for (int n = 0; n < 3000; ++n) {
    const int i = int(rng() % unsigned(spec.dims[0])), j = int(rng() % unsigned(spec.dims[1])),
              k = int(rng() % unsigned(spec.dims[2]));
    const Eigen::Vector3d p = spec.point(i, j, k);
    const double truth = std::min(kBand, brute_force(geo, p));
    const double inside = test::scene_signed_distance(scene, p) < 0 ? -1 : 1;
    const float v = f.values[std::size_t(i) +
                             std::size_t(spec.dims[0]) * (std::size_t(j) + std::size_t(spec.dims[1]) * std::size_t(k))];
    // The tessellation circumscribes curved primitives, so skip the sliver between them for the sign.
    if (std::abs(test::scene_signed_distance(scene, p)) < 0.003) continue;
    EXPECT_NEAR(v, inside * truth, 1e-5) << "at " << p.transpose();
    negative += v < 0;
    ++checked;
  }
  EXPECT_GT(checked, 2500);
  EXPECT_GT(negative, 50) << "the sample must reach inside obstacles";
}

TEST(EnvDistanceField, InterpolatedFieldAgreesWithAnalyticSdfWithinHalfACell) {
  const Scene scene = primitive_scene();
  const EnvironmentGeometry geo = make_environment_geometry(scene, 64);
  const EmbreeScene embree(geo);
  const runtime::Grid3 grid = runtime::to_grid(distance_field(embree, grid_covering(kBox, kRes), kBand, 2));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(-0.44, 0.44), uz(-0.09, 0.49);
  int compared = 0;
  for (int n = 0; n < 20000; ++n) {
    const Eigen::Vector3d p(ux(rng), ux(rng), uz(rng));
    double truth = test::scene_signed_distance(scene, p);
    // Inside, the field is the distance to the nearest surface of any obstacle, buried faces of
    // overlapping ones included (conservative: never deeper than the truth).
    if (truth < 0) {
      for (const auto& o : scene.objects)
        truth = std::max(truth, -std::abs(test::primitive_signed_distance(o.shapes[0], p)));
    }
    if (std::abs(truth) > kBand - 2 * kRes) continue;  // near the clamp, interpolation mixes in the band value
    const double v = grid.sample(p);
    EXPECT_NEAR(v, truth, 0.5 * kRes) << "at " << p.transpose();
    if (std::abs(truth) > 0.5 * kRes) {
      EXPECT_EQ(v < 0, truth < 0) << "sign at " << p.transpose();
    }
    ++compared;
  }
  EXPECT_GT(compared, 5000);
}

TEST(EnvDistanceField, FarCellsTakeTheBandAndOpenMeshesAreUnsigned) {
  Scene scene;
  Shape sheet;  // one open square, 2 triangles, at z = 0.2
  sheet.type = ShapeType::Mesh;
  sheet.size = Eigen::Vector3d::Ones();
  sheet.mesh.vertices.resize(4, 3);
  sheet.mesh.vertices << -0.2, -0.2, 0.2, 0.2, -0.2, 0.2, 0.2, 0.2, 0.2, -0.2, 0.2, 0.2;
  sheet.mesh.triangles.resize(2, 3);
  sheet.mesh.triangles << 0, 1, 2, 0, 2, 3;
  scene.objects.push_back({"sheet", {sheet}});
  const EnvironmentGeometry geo = make_environment_geometry(scene);
  ASSERT_FALSE(geo.closed.at(0));
  const EmbreeScene embree(geo);
  const GridSpec spec = grid_covering(kBox, kRes);
  const auto f = distance_field(embree, spec, kBand, 1);
  const runtime::Grid3 g = runtime::to_grid(f);
  EXPECT_NEAR(g.sample(Eigen::Vector3d(0, 0, 0.25)), 0.05, 1e-5);
  EXPECT_NEAR(g.sample(Eigen::Vector3d(0, 0, 0.15)), 0.05, 1e-5);  // below an open sheet: positive
  EXPECT_FLOAT_EQ(g.at(0, 0, 0), float(kBand));
  EXPECT_GE(*std::min_element(f.values.begin(), f.values.end()), 0.f);
}

TEST(EnvDistanceField, ScanPointsGiveUnsignedDistanceToTheNearestPoint) {
  Scene scene;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  scene.points.resize(500, 3);
  for (int i = 0; i < 500; ++i) scene.points.row(i) << u(rng), u(rng), 0.1 + 0.2 * u(rng);
  const EnvironmentGeometry geo = make_environment_geometry(scene);
  const EmbreeScene embree(geo);
  const GridSpec spec = grid_covering(kBox, 0.03);
  const auto f = distance_field(embree, spec, kBand, 2);
  for (int n = 0; n < 2000; ++n) {
    const int i = int(rng() % unsigned(spec.dims[0])), j = int(rng() % unsigned(spec.dims[1])),
              k = int(rng() % unsigned(spec.dims[2]));
    const Eigen::Vector3d p = spec.point(i, j, k);
    const float v = f.values[std::size_t(i) +
                             std::size_t(spec.dims[0]) * (std::size_t(j) + std::size_t(spec.dims[1]) * std::size_t(k))];
    EXPECT_NEAR(v, std::min(kBand, brute_force(geo, p)), 1e-5);
  }
}

TEST(EnvClearanceField, IgnoresTheSupportBelowButSeesWallsAndBoardsAbove) {
  Scene scene;
  scene.objects.push_back({"floor", {prim(ShapeType::Box, {1, 1, 0.04}, {0, 0, -0.02})}});
  scene.objects.push_back({"wall", {prim(ShapeType::Box, {0.04, 1, 0.6}, {0.3, 0, 0.3})}});
  scene.objects.push_back({"board", {prim(ShapeType::Box, {0.3, 0.3, 0.02}, {-0.2, 0, 0.31})}});
  const EnvironmentGeometry geo = make_environment_geometry(scene);
  const EmbreeScene embree(geo);
  const double band = 0.25;
  // Sample heights 0.005, 0.015, ...: none exactly on the floor's top face.
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.45, -0.45, -0.095), Eigen::Vector3d(0.45, 0.45, 0.5));
  const auto f = clearance_field(embree, grid_covering(box, 0.01), band, 2);
  const runtime::Grid3 g = runtime::to_grid(f);
  // Just above the floor, 0.1 m from the wall's face (x = 0.28): only the wall counts.
  EXPECT_NEAR(g.sample(Eigen::Vector3d(0.18, 0, 0.005)), 0.10, 1e-4);
  Eigen::Vector3d grad;
  g.sample(Eigen::Vector3d(0.185, 0.003, 0.01), grad);
  EXPECT_LT(grad.x(), -0.9) << "clearance grows away from the wall";
  // Under the board (underside z = 0.30): 0.2 m up.
  EXPECT_NEAR(g.sample(Eigen::Vector3d(-0.2, 0, 0.1)), 0.20, 1e-4);
  // In the open, far from the wall and not under the board: the band.
  EXPECT_NEAR(g.sample(Eigen::Vector3d(-0.1, -0.35, 0.4)), band, 1e-6);
  // Inside the wall: zero.
  EXPECT_NEAR(g.sample(Eigen::Vector3d(0.3, 0, 0.2)), 0.0, 1e-6);
  // The full distance field would see the floor: clearance must be larger there.
  EXPECT_NEAR(embree.distance(Eigen::Vector3d(0.18, 0, 0.05), 1.0), 0.05, 1e-9);
  EXPECT_NEAR(embree.distance_above(Eigen::Vector3d(0.18, 0, 0.05), 1.0, 0.05), 0.10, 1e-9);
}

TEST(EnvClosestPoint, ClippedTriangleDistanceMatchesDenseSampling) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 1), c(0, 1, 0.5), p(0.2, 0.8, 0.1);
  const double z_min = 0.45;
  double best = INFINITY;
  for (int i = 0; i <= 400; ++i)
    for (int j = 0; i + j <= 400; ++j) {
      const Eigen::Vector3d q = a + (b - a) * (i / 400.0) + (c - a) * (j / 400.0);
      if (q.z() > z_min) best = std::min(best, (q - p).norm());
    }
  EXPECT_NEAR(std::sqrt(squared_distance_to_triangle_above(p, a, b, c, z_min)), best, 3e-3);
  EXPECT_TRUE(std::isinf(squared_distance_to_triangle_above(p, a, b, c, 1.5)));
}
