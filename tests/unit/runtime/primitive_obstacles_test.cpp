// PrimitiveObstacles: exact distances to a scene's boxes, cylinders and spheres.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "collision_fixtures.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using namespace dmgplace::test::collision;

// PrimitiveObstacles::separations lists every primitive nearer a point than asked, with its exact
// distance and a direction along which every point of the primitive lies at least that distance
// short of the point (sampled points of the solid, rotated boxes, cylinders and spheres); a
// point inside one is reported.
TEST(PrimitiveObstacles, SeparationsListEveryNearPrimitiveWithASeparatingDirection) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  const Scene scene = random_primitives(rng, 9, 0.2);
  const auto prims = PrimitiveObstacles::from_scene(scene);
  ASSERT_TRUE(prims);
  std::vector<int> candidates;
  std::vector<PrimitiveObstacles::Separation> out;
  int listed = 0, inside = 0;
  for (int i = 0; i < 6000; ++i) {
    const Eigen::Vector3d p(1.3 * u(rng), 1.3 * u(rng), 1.3 * u(rng));
    const double within = 0.3 * std::abs(u(rng));
    prims->reaching(p, within, candidates);
    std::vector<double> distance;
    for (const auto& o : scene.objects) distance.push_back(shape_signed_distance(o.shapes[0], p));
    if (!prims->separations(p, within, candidates, out)) {
      EXPECT_LE(*std::min_element(distance.begin(), distance.end()), 1e-9) << "p = " << p.transpose();
      ++inside;
      continue;
    }
    for (std::size_t k = 0; k < distance.size(); ++k) {
      if (!(distance[k] < within)) continue;
      ASSERT_GT(distance[k], 0.0) << "p = " << p.transpose() << " is inside primitive " << k << " but nothing said so";
      const auto hit = std::find_if(out.begin(), out.end(),
                                    [&](const auto& s) { return std::abs(s.distance - distance[k]) < 1e-9; });
      ASSERT_NE(hit, out.end()) << "primitive " << k << " at " << distance[k] << " is not listed";
      ++listed;
      // Points of the solid: random in its bounding box, kept where the shape's distance says inside.
      const Shape& s = scene.objects[k].shapes[0];
      for (int m = 0; m < 200; ++m) {
        const Eigen::Vector3d y = s.origin * Eigen::Vector3d(u(rng) * s.size.x(), u(rng) * s.size.x(),
                                                             u(rng) * std::max(s.size.x(), s.size.y()));
        if (shape_signed_distance(s, y) > 0) continue;
        ASSERT_GE(hit->normal.dot(p - y), hit->distance - 1e-9) << "primitive " << k << ", p = " << p.transpose();
      }
    }
    EXPECT_LE(out.size(),
              std::size_t(std::count_if(distance.begin(), distance.end(), [&](double d) { return d < within; })));
  }
  EXPECT_GT(listed, 300);
  EXPECT_GT(inside, 10);
}

// PrimitiveObstacles::distance scans every primitive in double lanes, blocks of one type: on
// both SIMD paths it is the smallest signed distance of the shapes one by one, in scenes whose
// counts leave spare lanes (a block's spare lanes repeat a primitive), inside shapes too; no
// primitives, +inf.
TEST(PrimitiveObstacles, DistanceIsTheNearestShapesOnBothPaths) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    force_simd_path(path);
    EXPECT_EQ(PrimitiveObstacles::from_scene(Scene{})->distance(origin), std::numeric_limits<double>::infinity());
  }
  int inside = 0, checked = 0;
  for (int count = 1; count <= 13; count += 3) {
    const Scene scene = random_primitives(rng, count, 0.3);
    const auto prims = PrimitiveObstacles::from_scene(scene);
    ASSERT_TRUE(prims);
    for (int i = 0; i < 3000; ++i) {
      const Eigen::Vector3d p(1.5 * u(rng), 1.5 * u(rng), 1.5 * u(rng));
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& o : scene.objects) nearest = std::min(nearest, shape_signed_distance(o.shapes[0], p));
      force_simd_path(SimdPath::Portable);
      const double portable = prims->distance(p);
      force_simd_path(SimdPath::Avx2);
      const double avx2 = prims->distance(p);
      ASSERT_NEAR(portable, nearest, 1e-12) << count << " primitives, p = " << p.transpose();
      ASSERT_EQ(avx2, portable) << "the paths differ at p = " << p.transpose();
      inside += nearest < 0;
      ++checked;
    }
  }
  EXPECT_GT(inside, 100);
  RecordProperty("checked", checked);
}

// PrimitiveObstacles::distances (8 points per call in float lanes, what the scalar passes ask in
// exact scenes) is within float_error(limit) of distance() for points within `limit`, and bitwise
// the same on both SIMD paths: rotated boxes, cylinders and spheres, some scenes moved 4 m out
// (a larger extent), points inside shapes too, every lane a different point.
TEST(PrimitiveObstacles, FloatLaneDistancesAreWithinTheirErrorBoundOnBothPaths) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1, 1);
  constexpr int W = lanes::WF;
  int inside = 0, checked = 0;
  double worst = 0;                   // largest error seen, as a share of the bound
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (int count = 1; count <= 13; count += 3)
    for (const double shift : {0.0, 4.0, -4.0}) {
      Scene scene = random_primitives(rng, count, 0.3);
      for (auto& o : scene.objects) o.shapes[0].origin.translation().x() += shift;
      // One round with every other shape upright (turned about z only, as planning scenes'
      // tables and shelves are; the kernel then skips the products by zero).
      if (shift < 0)
        for (std::size_t k = 0; k < scene.objects.size(); k += 2) {
          const double a = 3 * u(rng), c = std::cos(a), s = std::sin(a);
          scene.objects[k].shapes[0].origin.linear() << c, -s, 0, s, c, 0, 0, 0, 1;
        }
      const auto prims = PrimitiveObstacles::from_scene(scene);
      ASSERT_TRUE(prims);
      const double limit = 1.5 + std::abs(shift);
      const double bound = prims->float_error(limit);
      for (int i = 0; i < 400; ++i) {
        alignas(32) float x[W], y[W], z[W], portable[W], avx2[W];
        for (int k = 0; k < W; ++k) {
          // Near the shapes mostly (the scene spans about [-1.3, 1.3] around its shift), the
          // limit's corner in one lane.
          const Eigen::Vector3d p = k == 0 && i % 50 == 0
                                        ? Eigen::Vector3d(limit, -limit, limit)
                                        : Eigen::Vector3d(shift + 1.5 * u(rng), 1.5 * u(rng), 1.5 * u(rng));
          x[k] = float(p.x());
          y[k] = float(p.y());
          z[k] = float(p.z());
        }
        force_simd_path(SimdPath::Portable);
        prims->distances(x, y, z, portable);
        force_simd_path(SimdPath::Avx2);
        prims->distances(x, y, z, avx2);
        for (int k = 0; k < W; ++k) {
          const Eigen::Vector3d p(x[k], y[k], z[k]);  // the float point is the point asked about
          const double exact = prims->distance(p);
          ASSERT_LE(std::abs(double(portable[k]) - exact), bound) << count << " primitives, p = " << p.transpose();
          ASSERT_EQ(avx2[k], portable[k]) << "the paths differ at p = " << p.transpose();
          worst = std::max(worst, std::abs(double(portable[k]) - exact) / bound);
          inside += exact < 0;
          ++checked;
        }
      }
    }
  EXPECT_GT(inside, 200);
  EXPECT_GT(worst, 0.0);  // floats do round: a path in doubles would not be this kernel
  RecordProperty("checked", checked);
  RecordProperty("worst_share_of_bound_x1000", int(1000 * worst));
}

// PrimitiveObstacles::clear_reaching_lanes, a body's bounding sphere in the lane check: its
// clear lanes are alive lanes at least `need` from every primitive but for float rounding, the
// other alive lanes closer; every primitive left out of `reach` is at least `need` from every
// alive lane; and clear_lanes over only the reached primitives gives the same lanes as over all
// (what the body's spheres rely on). Scenes of 1-13 primitives and one past 64 (no bits: all
// reached); random alive masks and needs; the portable build of the lanes.
TEST(PrimitiveObstacles, ClearAndReachingLanesAgreeWithExactDistances) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
  constexpr int W = lanes::WF;
  int left_out = 0, clear = 0, blocked = 0;
  for (const int count : {1, 4, 7, 10, 13, 70}) {
    const Scene scene = random_primitives(rng, count, 0.3);
    const auto prims = PrimitiveObstacles::from_scene(scene);
    ASSERT_TRUE(prims);
    const double bound = prims->float_error(2.0);
    for (int i = 0; i < 500; ++i) {
      alignas(32) float x[W], y[W], z[W];
      for (int k = 0; k < W; ++k) x[k] = float(1.5 * u(rng)), y[k] = float(1.5 * u(rng)), z[k] = float(1.5 * u(rng));
      const float need = float(0.02 + 0.3 * unit(rng));
      const auto alive = std::uint32_t(rng() & 0xff);
      std::uint64_t reach = 0;
      const std::uint32_t got = prims->clear_reaching_lanes(x, y, z, need, alive, reach);
      ASSERT_EQ(got & ~alive, 0u) << "a lane not asked about came back clear";
      ASSERT_EQ(prims->clear_lanes(x, y, z, need, alive, reach), got)
          << "the reached primitives alone decide otherwise";
      ASSERT_EQ(prims->clear_lanes(x, y, z, need, alive), got);
      if (!prims->all_have_bits()) {
        ASSERT_EQ(reach, ~std::uint64_t(0));
      }
      for (int k = 0; k < W; ++k) {
        if (!(alive >> k & 1u)) continue;
        const Eigen::Vector3d p(x[k], y[k], z[k]);
        const double d = prims->distance(p);
        if (got >> k & 1u) {
          ASSERT_GE(d, need - bound) << count << " primitives, p = " << p.transpose();
          ++clear;
        } else {
          ASSERT_LT(d, need + bound) << "blocked though clear: " << count << " primitives, p = " << p.transpose();
          ++blocked;
        }
        for (std::size_t o = 0; o < std::min<std::size_t>(scene.objects.size(), 64); ++o) {
          if (reach >> o & 1u) continue;
          ASSERT_GE(shape_signed_distance(scene.objects[o].shapes[0], p), need - bound)
              << "primitive " << o << " left out of reach, p = " << p.transpose();
          ++left_out;
        }
      }
    }
  }
  EXPECT_GT(clear, 1000);
  EXPECT_GT(blocked, 1000);
  EXPECT_GT(left_out, 1000);  // the reach mask does leave primitives out
  RecordProperty("clear", clear);
  RecordProperty("blocked", blocked);
}

// The exact primitive distance against FCL on the same scene: a ball slightly smaller than the
// distance is free, one slightly larger touches; inside an obstacle the distance is negative.
TEST(PrimitiveObstacles, DistanceAgreesWithFclOnBoxesCylindersAndSpheres) {
  ShelfWorld w;
  const auto obstacles = PrimitiveObstacles::from_scene(w.scene);
  ASSERT_TRUE(obstacles);
  ASSERT_EQ(obstacles->size(), 4u);
  ExactChecker exact(w.kin, w.scene);
  const double cos_face = std::cos(M_PI / 12);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> x(0.1, 1.0), y(-0.6, 0.6), z(0.2, 1.0);
  int near = 0, inside = 0;
  for (int i = 0; i < 3000 && near < 150; ++i) {
    const Eigen::Vector3d p(x(rng), y(rng), z(rng));
    const double d = obstacles->distance(p);
    Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
    at.translation() = p;
    if (d < 0) {
      ++inside;
      EXPECT_FALSE(exact.mesh_free(CollisionMesh(uv_sphere(0.002)), at)) << p.transpose() << " inside at " << d;
      continue;
    }
    if (d < 0.004 || d > 0.05) continue;  // small enough that no obstacle fits inside the larger ball
    ++near;
    EXPECT_TRUE(exact.mesh_free(CollisionMesh(uv_sphere(0.97 * d)), at)) << p.transpose() << " distance " << d;
    EXPECT_FALSE(exact.mesh_free(CollisionMesh(uv_sphere(1.03 * d / cos_face)), at))
        << p.transpose() << " distance " << d;
  }
  EXPECT_GE(near, 100);
  EXPECT_GE(inside, 20);
  // The last query's nearest shape first, the others skipped by their bounds: still the minimum
  // over every shape, wherever the previous point was.
  std::uniform_real_distribution<double> wide(-2.0, 2.0);
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p(wide(rng), wide(rng), wide(rng) + 0.5);
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& o : w.scene.objects)
      for (const auto& shape : o.shapes) brute = std::min(brute, shape_signed_distance(shape, p));
    EXPECT_NEAR(obstacles->distance(p), brute, 1e-12) << p.transpose();
  }
  EXPECT_EQ(PrimitiveObstacles::from_scene(Scene{}) ? PrimitiveObstacles::from_scene(Scene{})->size() : 99u, 0u);
  Scene with_mesh = w.scene;
  Shape mesh;
  mesh.type = ShapeType::Mesh;
  mesh.mesh = uv_sphere(0.1);
  with_mesh.objects.push_back({"mesh", {mesh}});
  EXPECT_FALSE(PrimitiveObstacles::from_scene(with_mesh)) << "a mesh is the field's job";
}
