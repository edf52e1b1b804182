#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <thread>

#include "analytic_sdf.hpp"
#include "dmgplace/formats/winding_number.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"
#include "fixtures.hpp"
#include "gap_certificates.hpp"
#include "lane_batches.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {
struct Arm {
  RobotModel model;
  std::vector<formats::LinkSphere> spheres;
};

Arm built_in_arm() {
  auto dir = test::source_dir() / "datasets/robots/dmgarm";
  Arm a;
  a.model = test::read_robot_model(dir / "dmgarm.urdf", dir / "dmgarm.srdf");
  a.spheres = test::robot_spheres(a.model);
  return a;
}

Shape box(const Eigen::Vector3d& size, const Eigen::Vector3d& at) { return test::box_shape(size, at); }

Scene shelf_scene() {
  Scene sc;
  sc.objects.push_back({"board", {box({0.4, 0.8, 0.03}, {0.6, 0, 0.45})}});
  sc.objects.push_back({"wall", {box({0.03, 0.8, 0.8}, {0.85, 0, 0.5})}});
  Shape can;
  can.type = ShapeType::Cylinder;
  can.size = Eigen::Vector3d(0.04, 0.15, 0);
  can.origin.translation() = Eigen::Vector3d(0.5, 0.25, 0.54);
  sc.objects.push_back({"can", {can}});
  Shape ball;
  ball.type = ShapeType::Sphere;
  ball.size = Eigen::Vector3d(0.06, 0, 0);
  ball.origin.translation() = Eigen::Vector3d(0.3, -0.4, 0.7);
  sc.objects.push_back({"ball", {ball}});
  return sc;
}

// The built-in arm (fingers half open) among the shelf scene's primitives, with their 2 cm field.
struct ShelfWorld {
  Arm arm = built_in_arm();
  Kinematics kin{arm.model, "dmgarm_link0", "dmgarm_tcp"};
  Scene scene = shelf_scene();
  std::shared_ptr<Grid3> sdf = test::analytic_sdf(
      scene, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, 0.3);
  ShelfWorld() { kin.set_joint_value("dmgarm_finger_joint1", 0.03); }
};

using test::batches_on_every_path;
using test::random_q;
}  // namespace

// Every form of the fast layer: the field alone; a scene of a few exact primitives, checked by
// their exact distances alone, with a field beside them or built without one; and one of more
// than 64, where the field goes first and the primitives settle what it leaves undecided (here
// the shelf plus 64 specks far out of reach, so the answers are the shelf's).
enum class Form { FieldOnly, WithExactPrimitives, ExactPrimitivesNoField, FieldWithManyPrimitives };
class FastLayer : public ::testing::TestWithParam<Form> {
 protected:
  SphereFieldChecker make(const ShelfWorld& w) const {
    if (GetParam() == Form::ExactPrimitivesNoField) return SphereFieldChecker(w.kin, w.arm.spheres, PrimitiveObstacles::from_scene(w.scene));
    SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
    if (GetParam() == Form::FieldOnly) return fast;
    Scene scene = w.scene;
    if (GetParam() == Form::FieldWithManyPrimitives)
      for (int k = 0; k < 64; ++k) {
        Shape speck;
        speck.type = ShapeType::Sphere;
        speck.size = Eigen::Vector3d(0.01, 0, 0);
        speck.origin.translation() = Eigen::Vector3d(0.1 * k - 3.2, 4.0, 3.0);
        scene.objects.push_back({"speck" + std::to_string(k), {speck}});
      }
    const auto obstacles = PrimitiveObstacles::from_scene(scene);
    EXPECT_EQ(obstacles->all_have_bits(), GetParam() == Form::WithExactPrimitives);
    fast.set_exact_obstacles(obstacles);
    return fast;
  }
  bool exact_primitives() const { return GetParam() != Form::FieldOnly; }
};
INSTANTIATE_TEST_SUITE_P(Collision, FastLayer,
                         ::testing::Values(Form::FieldOnly, Form::WithExactPrimitives, Form::ExactPrimitivesNoField,
                                           Form::FieldWithManyPrimitives),
                         [](const auto& info) {
                           return info.param == Form::FieldOnly                ? "FieldOnly"
                                  : info.param == Form::WithExactPrimitives    ? "WithExactPrimitives"
                                  : info.param == Form::ExactPrimitivesNoField ? "ExactPrimitivesNoField"
                                                                               : "FieldWithManyPrimitives";
                         });

// A scene of a few primitives needs no field: the checker built without one answers exactly as
// the one with a field beside the same primitives (which it never reads), state by state, along
// directions and in lanes; a scene the primitives cannot carry alone is refused.
TEST(FastLayerWithoutField, AnswersAsWithAFieldItNeverReads) {
  ShelfWorld w;
  const auto tables = test::self_distance_tables(w.kin, w.arm.spheres);
  const auto prims = PrimitiveObstacles::from_scene(w.scene);
  SphereFieldChecker with_field(w.kin, w.arm.spheres, w.sdf, 0.3);
  with_field.set_self_tables(tables);
  with_field.set_exact_obstacles(prims);
  SphereFieldChecker without(w.kin, w.arm.spheres, prims);
  without.set_self_tables(tables);
  EXPECT_TRUE(with_field.has_field());
  EXPECT_FALSE(without.has_field());
  std::mt19937_64 rng(23);
  int free = 0;
  for (int round = 0; round < 400; ++round) {
    std::vector<Eigen::VectorXd> qs;
    const double* ptr[PoseBatch::kLanes];
    for (int k = 0; k < PoseBatch::kLanes; ++k) qs.push_back(random_q(w.kin, rng));
    for (int k = 0; k < PoseBatch::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
    const Eigen::VectorXd dir = random_q(w.kin, rng) - qs[0];
    ASSERT_EQ(with_field.free_lanes(ptr), without.free_lanes(ptr));
    ASSERT_EQ(with_field.free_lanes_along(ptr, PoseBatch::kLanes, dir, 0.05), without.free_lanes_along(ptr, PoseBatch::kLanes, dir, 0.05));
    const SphereCheck a = with_field.check_along(qs[0], dir), b = without.check_along(qs[0], dir);
    ASSERT_EQ(a.free(), b.free());
    ASSERT_EQ(a.env_link_count, b.env_link_count);
    ASSERT_EQ(a.pair_count, b.pair_count);
    ASSERT_EQ(a.proven_collision, b.proven_collision);
    ASSERT_EQ(a.free_distance, b.free_distance);
    free += a.free();
  }
  EXPECT_GT(free, 40);
  Scene many = w.scene;
  for (int k = 0; k < 64; ++k) many.objects.push_back({"speck", {box({0.01, 0.01, 0.01}, {0.1 * k, 4.0, 3.0})}});
  EXPECT_THROW(SphereFieldChecker(w.kin, w.arm.spheres, PrimitiveObstacles::from_scene(many)), Error);
  EXPECT_THROW(SphereFieldChecker(w.kin, w.arm.spheres, std::shared_ptr<const PrimitiveObstacles>()), Error);
  EXPECT_THROW(without.set_exact_obstacles(nullptr), Error);
}

// A checker moved to another scene keeps the robot's geometry and answers as one built there.
TEST(ExactChecker, WithSceneAnswersAsACheckerBuiltForThatScene) {
  ShelfWorld w;
  const ExactChecker empty(w.kin, Scene{});
  const ExactChecker moved = empty.with_scene(w.scene), fresh(w.kin, w.scene);
  std::mt19937_64 rng(29);
  int collide = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::VectorXd q = random_q(w.kin, rng);
    const ExactCheck a = moved.check(q), b = fresh.check(q);
    ASSERT_EQ(a.environment_free, b.environment_free);
    ASSERT_EQ(a.self_free, b.self_free);
    ASSERT_TRUE(empty.check(q).environment_free);
    collide += !a.environment_free;
  }
  EXPECT_GT(collide, 10);
}

TEST_P(FastLayer, NeverSaysFreeWhereExactLayerCollides) {
  ShelfWorld w;
  const auto& [arm, kin, scene, sdf] = w;
  SphereFieldChecker fast = make(w);
  ExactChecker exact(kin, scene);
  TwoLayerChecker both_layers(fast, exact);
  std::mt19937_64 rng(42);
  int fast_free = 0, exact_free = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd q = random_q(kin, rng);
    const bool f = fast.is_free(q), e = exact.is_free(q);
    fast_free += f;
    exact_free += e;
    ASSERT_FALSE(f && !e) << "fast layer said free where FCL collides: q = " << q.transpose() << " ("
                          << exact.check(q).contact << ")";
    ASSERT_EQ(both_layers.is_free(q), e) << "the two-layer answer must be the exact answer";
  }
  // The sphere layer must settle the environment on its own most of the time, or it is no layer.
  const long full = both_layers.counters().exact_full.load();
  EXPECT_LT(full, long(n) / 2) << "full exact checks: " << full << " of " << n;
  // With exact primitives the inner balls prove collisions (each one agreed with FCL above).
  if (exact_primitives()) {
    EXPECT_GT(both_layers.counters().proven_collisions.load(), long(n) / 50);
  }
  RecordProperty("fast_free", fast_free);
  RecordProperty("exact_full", int(full));
  RecordProperty("exact_free", exact_free);
}

// Issue 20: 8 configurations per call. Batch forward kinematics equals the scalar one, on the
// AVX2 path (where the CPU has it) and on the portable one, with the base at the root and not.
TEST(Batch, ForwardKinematicsEqualsTheScalarOneOnEveryPath) {
  Arm arm = built_in_arm();
  for (const char* base : {"dmgarm_link0", "dmgarm_link2"}) {
    Kinematics kin(arm.model, base, "dmgarm_tcp");
    kin.set_joint_value("dmgarm_finger_joint1", 0.021);  // a mimic follows it
    batches_on_every_path(kin, 3, 50, [](int, Eigen::VectorXd&) {}, [&](const std::vector<Eigen::VectorXd>& qs, const double* const* ptr) {
      PoseBatch batch;
      kin.link_poses_batch(ptr, batch);
      std::vector<Eigen::Isometry3d> poses;
      for (int k = 0; k < PoseBatch::kLanes; ++k) {
        kin.link_poses(qs[std::size_t(k)], poses);
        for (std::size_t l = 0; l < poses.size(); ++l)
          for (int e = 0; e < 12; ++e) {
            const double want = e < 9 ? poses[l].linear()(e / 3, e % 3) : poses[l].translation()[e - 9];
            ASSERT_NEAR(batch.pose[l][std::size_t(e)][std::size_t(k)], want, 1e-12)
                << base << " " << to_string(simd_path()) << " link " << l << " element " << e;
          }
      }
    });
  }
}

// The float batch (what the batch sphere check runs on) stays within Kinematics::float_pose_error
// of the double poses, for points within `reach` of their link: on every path, the base at the
// root and not, prismatic mimic fingers set. And the bound is tight enough to be of use.
TEST(Batch, FloatForwardKinematicsStaysWithinItsErrorBound) {
  Arm arm = built_in_arm();
  const double reach = 1.5;
  for (const char* base : {"dmgarm_link0", "dmgarm_link2"}) {
    Kinematics kin(arm.model, base, "dmgarm_tcp");
    kin.set_joint_value("dmgarm_finger_joint1", 0.021);
    const double bound = kin.float_pose_error(reach);
    EXPECT_GT(bound, 0.0);
    EXPECT_LT(bound, 1e-4) << "a bound this loose would cost the batch its proofs";
    double worst = 0;
    auto wide_angles = [](int round, Eigen::VectorXd& q) {
      if (round % 4 == 0) q *= 40.0;  // sin and cos far from the first turn
    };
    batches_on_every_path(kin, 5, 200, wide_angles, [&](const std::vector<Eigen::VectorXd>& qs, const double* const* ptr) {
      PoseBatchF batch;
      kin.link_poses_batch(ptr, batch);
      std::vector<Eigen::Isometry3d> poses;
      for (int k = 0; k < PoseBatch::kLanes; ++k) {
        kin.link_poses(qs[std::size_t(k)], poses);
        for (std::size_t l = 0; l < poses.size(); ++l)
          for (int axis = 0; axis < 7; ++axis) {
            Eigen::Vector3d p = Eigen::Vector3d::Zero();
            if (axis < 6) p[axis % 3] = axis < 3 ? reach : -reach;
            const auto& e = batch.pose[l];
            auto at = [&](int i) { return e[std::size_t(i)][std::size_t(k)]; };
            Eigen::Vector3d got;
            for (int r = 0; r < 3; ++r)
              got[r] = double(at(3 * r) * float(p.x()) + at(3 * r + 1) * float(p.y()) + at(3 * r + 2) * float(p.z()) + at(9 + r));
            const double err = (got - poses[l] * p).norm();
            worst = std::max(worst, err);
            ASSERT_LE(err, bound) << base << " " << to_string(simd_path()) << " link " << l << " point " << axis;
          }
      }
    });
    RecordProperty(std::string("worst_over_bound_") + base, std::to_string(worst / bound));
    std::cout << base << ": worst float error " << worst << " m, bound " << bound << " m\n";
  }
}

// A lane the batch proves free is free for the scalar fast layer (hence for FCL, by the test
// above), and the batch proves most of what the scalar layer proves: on both paths, with the
// self-distance tables, with a held object, and with the scene's exact primitives (which the batch
// trusts outside the grid too, so there FCL is the judge).
TEST(Batch, FreeLanesAreFreeForTheScalarLayerAndFclAndMostAreProven) {
  ShelfWorld w;
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  const int tcp = w.arm.model.link_index("dmgarm_tcp");
  AttachedSpheres object;
  object.link = tcp;
  object.centers = {Eigen::Vector3d(0, 0, 0.02), Eigen::Vector3d(0, 0, 0.06)};
  object.radii = {0.025, 0.025};
  object.touching_links = {w.arm.model.link_index("dmgarm_leftfinger"), w.arm.model.link_index("dmgarm_rightfinger")};
  const SphereFieldChecker held = fast.with_attached(object);
  SphereFieldChecker primitives = fast;
  primitives.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  ASSERT_TRUE(primitives.free_lanes(std::array<const double*, 1>{w.kin.lower().data()}.data(), 1) <= 1u);
  ExactChecker exact(w.kin, w.scene);
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SphereFieldChecker* checker : std::initializer_list<const SphereFieldChecker*>{&fast, &held, &primitives})
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
      force_simd_path(path);
      std::mt19937_64 rng(11);
      int scalar_free = 0, batch_free = 0;
      for (int round = 0; round < 1500; ++round) {
        std::vector<Eigen::VectorXd> qs;
        const double* ptr[PoseBatch::kLanes];
        for (int k = 0; k < PoseBatch::kLanes; ++k) qs.push_back(random_q(w.kin, rng));
        for (int k = 0; k < PoseBatch::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
        const int count = 1 + round % PoseBatch::kLanes;  // partial batches too
        const std::uint32_t mask = checker->free_lanes(ptr, count);
        EXPECT_EQ(mask >> count, 0u);
        for (int k = 0; k < count; ++k) {
          const bool scalar = checker->check(qs[std::size_t(k)]).free(), batch = mask >> k & 1u;
          scalar_free += scalar;
          batch_free += batch;
          if (checker != &primitives) {
            ASSERT_FALSE(batch && !scalar) << "batch said free where the scalar layer does not: " << qs[std::size_t(k)].transpose();
          }
          if (checker != &held) {
            ASSERT_FALSE(batch && !exact.is_free(qs[std::size_t(k)])) << qs[std::size_t(k)].transpose();
          }
        }
      }
      EXPECT_GT(scalar_free, 100);
      EXPECT_GE(batch_free, scalar_free * 9 / 10) << "the batch proves " << batch_free << " of " << scalar_free;
    }
}

// The batch works in floats, forward kinematics included: its rounding margin must hold exactly where
// it matters, at the edge of "free". With the scene's exact primitives the scalar layer's verdict
// on the scene is continuous (every sphere's exact distance), so bisecting between a configuration
// it proves free and one where only the scene stops it gives one within 1e-12 of that edge on the
// blocked side; there the batch must not say free. (Float rounding is ~1e-7 m: with the margin
// set to 0 this fails. The field's nearest-node bound jumps between nodes, so its edges are no
// test of rounding.)
TEST(Batch, FloatLanesStayConservativeAtTheEdgeOfTheScene) {
  ShelfWorld w;
  SphereFieldChecker checker(w.kin, w.arm.spheres, w.sdf, 0.3);
  checker.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  checker.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    force_simd_path(path);
    std::mt19937_64 rng(5);
    for (int batch = 0; batch < 60; ++batch) {
      std::vector<Eigen::VectorXd> qs;
      while (int(qs.size()) < PoseBatch::kLanes) {
        Eigen::VectorXd a = random_q(w.kin, rng), b = random_q(w.kin, rng);
        if (!checker.is_free(a) || checker.is_free(b)) continue;
        for (int i = 0; i < 45; ++i) {  // a stays free, b not
          const Eigen::VectorXd m = 0.5 * (a + b);
          (checker.is_free(m) ? a : b) = m;
        }
        const SphereCheck edge = checker.check(b);
        if (!edge.environment_free && edge.self_free) qs.push_back(b);
      }
      const double* ptr[PoseBatch::kLanes];
      for (int k = 0; k < PoseBatch::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
      ASSERT_EQ(checker.free_lanes(ptr), 0u) << "the batch said free just past the scene's edge";
    }
  }
}

// The float margin is the kinematics' as they are when a batch runs: setting a joint outside the
// chain moves the float poses' error bound (a prismatic joint's offset enters it; the fingers set
// 2 m out, as a long lift outside the chain would be, make it the largest), and a checker built
// before follows it, as one built afresh has it grow. (The two differ: the fresh one carries the
// fingers 2 m from the frame they ride, Kinematics::batch_frame; the one built before, whose
// offsets are stale, places them from their own links.)
TEST(Batch, LaneMarginFollowsJointsSetOutsideTheChain) {
  ShelfWorld w;
  SphereFieldChecker before(w.kin, w.arm.spheres, w.sdf, 0.3);
  before.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  const double was = before.lane_margin();
  w.kin.set_joint_value("dmgarm_finger_joint1", 2.0);
  SphereFieldChecker fresh(w.kin, w.arm.spheres, w.sdf, 0.3);
  fresh.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  EXPECT_GT(fresh.lane_margin(), was) << "the fingers' value does not enter the bound: nothing to follow";
  EXPECT_GT(before.lane_margin(), was) << "a checker built before kept its margin";
}

// A checker built before a joint outside the chain is set places its bodies from their own links
// (the batch frames it carried them into moved): its free lanes stay free for FCL with the
// fingers as they are now, and it proves as much as a checker built afresh. The fingers go from
// closed to 0.3 m out (as a lift outside the chain would move a link), so a batch still placing
// them closed says free where they now hit.
TEST(Batch, FreeLanesFollowJointsSetAfterTheCheckerWasBuilt) {
  ShelfWorld w;
  w.kin.set_joint_value("dmgarm_finger_joint1", 0.3);
  const auto tables = test::self_distance_tables(w.kin, w.arm.spheres);  // as the fingers end
  auto checker = [&] {
    SphereFieldChecker c(w.kin, w.arm.spheres, w.sdf, 0.3);
    c.set_self_tables(tables);
    c.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
    return c;
  };
  w.kin.set_joint_value("dmgarm_finger_joint1", 0.0);
  const SphereFieldChecker before = checker();
  w.kin.set_joint_value("dmgarm_finger_joint1", 0.3);
  const SphereFieldChecker fresh = checker();
  ExactChecker exact(w.kin, w.scene);
  int before_free[2] = {0, 0}, fresh_free[2] = {0, 0};  // per path: portable, AVX2
  batches_on_every_path(w.kin, 21, 800, [&](const std::vector<Eigen::VectorXd>& qs, const double* const* ptr) {
    const int at = simd_path() == SimdPath::Avx2;
    const std::uint32_t a = before.free_lanes(ptr), b = fresh.free_lanes(ptr);
    before_free[at] += __builtin_popcount(a);
    fresh_free[at] += __builtin_popcount(b);
    for (int k = 0; k < PoseBatch::kLanes; ++k) {
      if (!((a | b) >> k & 1u)) continue;
      ASSERT_TRUE(exact.is_free(qs[std::size_t(k)])) << to_string(simd_path()) << " " << qs[std::size_t(k)].transpose();
    }
  });
  for (int at = 0; at < 2; ++at) {
    EXPECT_GT(fresh_free[at], 1000);
    EXPECT_GE(before_free[at], fresh_free[at] * 99 / 100) << "path " << at;
    EXPECT_GE(fresh_free[at], before_free[at] * 99 / 100) << "path " << at;
    std::cout << (at ? "avx2" : "portable") << ": " << before_free[at] << " free by the checker built before, "
              << fresh_free[at] << " afresh\n";
  }
}

// A lane proven along a direction proves every state within its reach: each one sampled 2.5 mrad
// apart is free for the scalar layer (FCL with the scene's exact primitives, which the batch
// trusts outside the grid too). The test finds lanes whose centre alone is free but some state
// within reach is not, so a batch that widened nothing would fail it; reach 0 is free_lanes.
namespace {
// 8 random configurations (and their pointers, as free_lanes takes them) and a random unit
// direction (from n, which keeps its spare draw between batches), drawn in that order.
struct RandomBatch {
  std::vector<Eigen::VectorXd> qs;
  const double* ptr[PoseBatch::kLanes];
  Eigen::VectorXd u;
  RandomBatch(const Kinematics& kin, std::mt19937_64& rng, std::normal_distribution<double>& n) {
    for (int k = 0; k < PoseBatch::kLanes; ++k) qs.push_back(random_q(kin, rng));
    for (int k = 0; k < PoseBatch::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
    u.resize(kin.dof());
    for (int i = 0; i < u.size(); ++i) u[i] = n(rng);
    u.normalize();
  }
  RandomBatch(const RandomBatch&) = delete;  // ptr points into qs
};

// The fast layer three ways for free_lanes_along's tests: the field, the same holding an object
// (two spheres), and with the scene's exact primitives; with or without self tables. Two judges
// that know the true geometry (a proof holds for true distances, not for the scalar field check,
// whose node bounds lose up to a cell's slope):
// - `judge`, FCL for the robot (the self tables bound the meshes' distance, so only the meshes can
//   judge their proofs), and for the held object its spheres' exact distances to the scene's
//   primitives and to the robot spheres it may not touch;
// - `sphere_judge`: for the scene, the scalar check with the exact primitives, which is the sphere
//   model's truth (every undecided sphere asks the exact distance), so the slack between spheres
//   and meshes does not hide a bound too small; for the rest, `judge`.
struct AlongCheckers {
  ShelfWorld w;
  SphereFieldChecker fast{w.kin, w.arm.spheres, w.sdf, 0.3};
  SphereFieldChecker held, primitives, held_primitives;
  ExactChecker exact{w.kin, w.scene};
  AttachedSpheres object;
  std::shared_ptr<const PrimitiveObstacles> scene = PrimitiveObstacles::from_scene(w.scene);
  explicit AlongCheckers(bool tables) : held(fast), primitives(fast), held_primitives(fast) {
    if (tables) fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
    object.link = w.arm.model.link_index("dmgarm_tcp");
    object.centers = {Eigen::Vector3d(0, 0, 0.02), Eigen::Vector3d(0, 0, 0.06)};
    object.radii = {0.025, 0.025};
    object.touching_links = {w.arm.model.link_index("dmgarm_leftfinger"), w.arm.model.link_index("dmgarm_rightfinger")};
    held = fast.with_attached(object);
    primitives = fast;
    primitives.set_exact_obstacles(scene);
    held_primitives = primitives.with_attached(object);
  }
  std::array<const SphereFieldChecker*, 3> all() const { return {&fast, &held, &primitives}; }
  bool judge(const SphereFieldChecker* checker, const Eigen::VectorXd& q) const {
    if (!exact.is_free(q)) return false;
    if (checker != &held) return true;
    std::vector<Eigen::Isometry3d> poses;
    w.kin.link_poses(q, poses);
    for (std::size_t i = 0; i < object.centers.size(); ++i) {
      const Eigen::Vector3d p = poses[std::size_t(object.link)] * object.centers[i];
      if (scene->distance(p) < object.radii[i]) return false;
      for (const auto& s : w.arm.spheres) {
        const auto& t = object.touching_links;
        if (s.link == object.link || std::find(t.begin(), t.end(), s.link) != t.end()) continue;
        if ((poses[std::size_t(s.link)] * s.center - p).norm() < s.radius + object.radii[i]) return false;
      }
    }
    return true;
  }
  bool sphere_judge(const SphereFieldChecker* checker, const Eigen::VectorXd& q) const {
    return (checker == &held ? held_primitives : primitives).check(q).environment_free && judge(checker, q);
  }
};
}  // namespace

TEST(Batch, LanesAlongADirectionProveEveryStateWithinTheirReach) {
  const AlongCheckers c(true);
  const ShelfWorld& w = c.w;
  int near_misses = 0;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SphereFieldChecker* checker : c.all())
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
      force_simd_path(path);
      auto judge = [&](const Eigen::VectorXd& q) { return c.judge(checker, q); };
      std::mt19937_64 rng(17);
      std::normal_distribution<double> n(0, 1);
      int proven = 0;
      for (int round = 0; round < 160; ++round) {
        const RandomBatch batch(w.kin, rng, n);
        const auto& qs = batch.qs;
        const auto& ptr = batch.ptr;
        const auto& u = batch.u;
        const double reach = round % 2 ? 0.08 : 0.03;
        const std::uint32_t alone = checker->free_lanes(ptr), along = checker->free_lanes_along(ptr, PoseBatch::kLanes, u, reach);
        ASSERT_EQ(checker->free_lanes_along(ptr, PoseBatch::kLanes, u, 0.0), alone);
        ASSERT_EQ(along & ~alone, 0u) << "proven along but not alone";
        for (int k = 0; k < PoseBatch::kLanes; ++k) {
          if (!(alone >> k & 1u)) continue;
          bool all_free = true;
          for (double t = -reach; t <= reach + 1e-12 && all_free; t += 0.0025) all_free = judge(qs[std::size_t(k)] + t * u);
          near_misses += !all_free;
          if (!(along >> k & 1u)) continue;
          ++proven;
          ASSERT_TRUE(all_free) << "lane " << k << " proven for " << reach << " along " << u.transpose() << " from "
                                << qs[std::size_t(k)].transpose();
        }
      }
      EXPECT_GT(proven, 60) << to_string(path);
    }
  EXPECT_GT(near_misses, 10) << "no lane was free alone and blocked within reach: the test cannot tell";
  RecordProperty("near_misses", near_misses);
}

// free_lanes_along's widening bounds every motion it covers: over +-reach along the direction,
// no point of a body's spheres (the held object's too) moves farther than its bound, and no two
// points of a checked pair change their distance by more than the pair's, lane by lane. The
// bounds are tight where the lanes' own lever arms are used: the largest ratio of motion to bound
// comes near 1 (so a bound a fifth too small fails here), where the static bound alone stays far
// below.
TEST(Batch, MotionBoundsCoverEveryPointOfEachBodyAndPair) {
  const AlongCheckers c(true);
  const ShelfWorld& w = c.w;
  std::mt19937_64 rng(29);
  std::normal_distribution<double> n(0, 1);
  // Points of a link's spheres (held object's, for the attached body): centres and six extremes.
  auto points = [&](int link, bool attached) {
    std::vector<Eigen::Vector3d> out;
    auto add = [&](const Eigen::Vector3d& centre, double r) {
      out.push_back(centre);
      for (int i = 0; i < 3; ++i)
        for (const double sign : {-1.0, 1.0}) out.push_back(centre + sign * r * Eigen::Vector3d::Unit(i));
    };
    if (attached)
      for (std::size_t i = 0; i < c.object.centers.size(); ++i) add(c.object.centers[i], c.object.radii[i]);
    else
      for (const auto& s : w.arm.spheres)
        if (s.link == link) add(s.center, s.radius);
    return out;
  };
  double worst = 0;
  int bodies = 0, pairs = 0, batches = 0;
  std::vector<Eigen::Isometry3d> p0, pt;
  for (int round = 0; round < 40; ++round) {
    const RandomBatch batch(w.kin, rng, n);
    const auto& qs = batch.qs;
    const auto& ptr = batch.ptr;
    const auto& u = batch.u;
    const double reach = std::array{0.01, 0.04, 0.12}[std::size_t(round % 3)];
    const auto bounds = c.held.motion_bounds(ptr, PoseBatch::kLanes, u, reach);
    if (bounds.empty()) continue;
    ++batches;
    for (int k = 0; k < PoseBatch::kLanes; ++k) {
      w.kin.link_poses(qs[std::size_t(k)], p0);
      for (int step = -10; step <= 10; ++step) {
        if (step == 0) continue;
        w.kin.link_poses(qs[std::size_t(k)] + (reach * step / 10.0) * u, pt);
        for (const auto& b : bounds) {
          const double bound = b.metres[std::size_t(k)];
          const bool held_a = b.attached && (b.link_b < 0 || b.link_a == c.object.link);
          const auto pa = points(b.link_a, held_a);
          double moved = 0;
          if (b.link_b < 0) {
            for (const auto& x : pa)
              moved = std::max(moved, (pt[std::size_t(b.link_a)] * x - p0[std::size_t(b.link_a)] * x).norm());
            bodies += step == 10;
          } else {
            const auto pb = points(b.link_b, b.attached && !held_a);
            for (const auto& x : pa)
              for (const auto& y : pb) {
                const double d0 = (p0[std::size_t(b.link_a)] * x - p0[std::size_t(b.link_b)] * y).norm();
                const double d1 = (pt[std::size_t(b.link_a)] * x - pt[std::size_t(b.link_b)] * y).norm();
                moved = std::max(moved, std::abs(d1 - d0));
              }
            pairs += step == 10;
          }
          ASSERT_LE(moved, bound + 1e-9) << "link " << b.link_a << (b.link_b >= 0 ? " with " + std::to_string(b.link_b) : "")
                                         << ", lane " << k << ", reach " << reach << ", step " << step;
          if (bound > 0) worst = std::max(worst, moved / bound);
        }
      }
    }
  }
  EXPECT_GT(batches, 30);
  EXPECT_GT(bodies, 1000);
  EXPECT_GT(pairs, 1000);
  EXPECT_GT(worst, 0.85) << "the bounds are loose everywhere: a bound too small would pass";
  RecordProperty("largest_motion_over_bound", std::to_string(worst));
}

// Lanes lined up short of a collision, heading for it, most within one reach of it: a lane whose
// reach takes in the collision must not be proven, however clear the lane's own state. Many such
// lanes are proven free alone (free_lanes), so only the widening stands between them and a wrong
// proof (with no widening this fails at once).
TEST(Batch, LanesHeadingForACollisionAreNotProvenPastIt) {
  const AlongCheckers c(true);
  const ShelfWorld& w = c.w;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SphereFieldChecker* checker : c.all())
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
      force_simd_path(path);
      auto judge = [&](const Eigen::VectorXd& q) { return c.sphere_judge(checker, q); };
      std::mt19937_64 rng(23);
      std::normal_distribution<double> n(0, 1);
      int cases = 0, free_alone = 0;
      for (int attempt = 0; attempt < 4000 && cases < 20; ++attempt) {
        const Eigen::VectorXd q = random_q(w.kin, rng);
        Eigen::VectorXd u(w.kin.dof());
        for (int i = 0; i < u.size(); ++i) u[i] = n(rng);
        u.normalize();
        if (!judge(q)) continue;
        double hit = -1;  // the first blocked state along u, 2.5 mrad apart
        for (double t = 0.0025; t <= 0.4 && hit < 0; t += 0.0025)
          if (!judge(q + t * u)) hit = t;
        if (hit < 0.05) continue;
        ++cases;
        const double reach = std::min(0.04, hit / 2);
        auto short_of = [&](int k) { return reach * (0.15 + 0.125 * k); };  // 0.15 .. 1.025 reaches short of it
        std::vector<Eigen::VectorXd> qs;
        const double* ptr[PoseBatch::kLanes];
        for (int k = 0; k < PoseBatch::kLanes; ++k) qs.push_back(q + (hit - short_of(k)) * u);
        for (int k = 0; k < PoseBatch::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
        const std::uint32_t along = checker->free_lanes_along(ptr, PoseBatch::kLanes, u, reach);
        const std::uint32_t alone = checker->free_lanes(ptr);
        for (int k = 0; k < PoseBatch::kLanes; ++k) {
          if (!(short_of(k) < reach)) continue;
          free_alone += alone >> k & 1u;
          ASSERT_FALSE(along >> k & 1u) << to_string(path) << ": lane " << k << " proven " << short_of(k) / reach
                                        << " reaches short of a collision";
        }
      }
      EXPECT_GE(cases, 20) << to_string(path);
      EXPECT_GT(free_alone, 3) << to_string(path) << ": the lanes are not free alone, the test cannot tell";
    }
}

TEST(Collision, HomePoseIsFreeAndObstaclesAtTheHandAreCaught) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  Eigen::VectorXd home(7);
  home << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  Scene empty;
  empty.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 3, 3})}});
  ExactChecker exact(kin, empty);
  EXPECT_TRUE(exact.check(home).free()) << exact.check(home).contact;
  auto sdf = test::analytic_sdf(empty, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, 0.3);
  SphereFieldChecker fast(kin, arm.spheres, sdf, 0.3);
  // Home folds link 7 close to link 5: the spheres may not tell, the two layers must.
  EXPECT_TRUE(TwoLayerChecker(fast, exact).is_free(home));
  // A box around the tool centre point collides in both layers.
  Scene blocked = empty;
  const Eigen::Vector3d tcp = kin.tip_pose(home).translation();
  blocked.objects.push_back({"block", {box({0.05, 0.05, 0.05}, tcp)}});
  ExactChecker exact2(kin, blocked);
  auto sdf2 = test::analytic_sdf(blocked, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, 0.3);
  SphereFieldChecker fast2(kin, arm.spheres, sdf2, 0.3);
  EXPECT_FALSE(exact2.is_free(home));
  EXPECT_FALSE(fast2.is_free(home));
  EXPECT_NE(exact2.check(home).contact.find("block"), std::string::npos);
}

// Per-query checkers build FCL objects over the world's shared meshes while other queries run,
// and FCL's object constructor rewrites its geometry's bounds (a mesh's radius passes through 0
// and its square). A rod whose only contact is at its far end is found every time, however many
// checkers other threads build over the same mesh meanwhile.
TEST(Collision, MeshChecksHoldWhileOtherThreadsBuildCheckersOverTheSameMesh) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  Eigen::VectorXd home(7);
  home << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  // A 1 m rod along x; many copies of its centre after the corners make FCL's bound loops long.
  TriMesh rod = test::box_mesh({1.0, 0.02, 0.02});
  const Eigen::Index corners = rod.vertices.rows();
  rod.vertices.conservativeResize(corners + 200000, 3);
  rod.vertices.bottomRows(200000).setZero();
  const CollisionMesh mesh(rod);
  // Turned (FCL then bounds it by its sphere), touching a block with its far end only.
  const Eigen::Isometry3d pose(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  Scene scene;
  scene.objects.push_back({"block", {box({0.04, 0.04, 0.04}, pose * Eigen::Vector3d(0.5, 0, 0))}});
  const ExactChecker exact(kin, scene);
  ASSERT_FALSE(exact.mesh_free(mesh, pose));
  std::atomic<bool> done{false};
  std::thread builders([&] {
    for (int i = 0; i < 40; ++i) {
      const ExactChecker held = exact.with_attached(mesh, kin.tip_link(), Eigen::Isometry3d::Identity(), {});
      (void)held.is_free(home);  // its first query builds its objects, the rod's among them
    }
    done = true;
  });
  long checks = 0, missed = 0;
  while (!done) {
    ++checks;
    missed += exact.mesh_free(mesh, pose);
  }
  builders.join();
  EXPECT_EQ(missed, 0) << "of " << checks << " checks";
  EXPECT_GT(checks, 0);
}

TEST(Collision, SelfCollisionRespectsAllowedPairs) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  Scene empty;
  empty.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 3, 3})}});
  ExactChecker exact(kin, empty);
  auto sdf = test::analytic_sdf(empty, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, 0.3);
  SphereFieldChecker fast(kin, arm.spheres, sdf, 0.3);
  std::mt19937_64 rng(9);
  int self_hits = 0;
  for (int i = 0; i < 5000; ++i) {
    Eigen::VectorXd q = random_q(kin, rng);
    auto e = exact.check(q);
    self_hits += !e.self_free;
    if (fast.is_free(q)) {
      ASSERT_TRUE(e.free()) << e.contact;
    }
  }
  EXPECT_GT(self_hits, 0) << "random configurations of a 7-DOF arm fold into themselves sometimes";
}

// The scalar passes' pair test (SphereFieldChecker::pair_contact: each body's spheres in its own
// frame, four at a time) flags exactly the link pairs whose spheres a world-frame loop over every
// sphere pair finds overlapping (padding counted once), on each SIMD path; the certified check's
// own loop flags the same ones.
TEST(Collision, FlaggedSelfPairsAreThoseWhoseSpheresOverlap) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  kin.set_joint_value("dmgarm_finger_joint1", 0.02);
  Scene empty;
  empty.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 3, 3})}});
  auto sdf = test::analytic_sdf(empty, Eigen::AlignedBox3d(Eigen::Vector3d(-1.6, -1.6, -1.0), Eigen::Vector3d(1.6, 1.6, 2.0)), 0.04, 0.3);
  const double padding = 0.005;
  const SphereFieldChecker fast(kin, arm.spheres, sdf, 0.3, padding);
  const auto moving = kin.moving_links();
  auto allowed = [&](int a, int b) {
    for (auto [x, y] : kin.model().allowed_pairs)
      if ((x == a && y == b) || (x == b && y == a)) return true;
    return false;
  };
  std::vector<Eigen::Isometry3d> poses;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    force_simd_path(path);
    std::mt19937_64 rng(21);
    int proven = 0, overflow = 0;
    std::set<std::set<std::pair<int, int>>> kinds;  // sets of flagged pairs seen
    for (int n = 0; n < 3000; ++n) {
      const Eigen::VectorXd q = random_q(kin, rng);
      kin.link_poses(q, poses);
      std::set<std::pair<int, int>> expect;
      for (const auto& s : arm.spheres)
        for (const auto& t : arm.spheres) {
          if (s.link >= t.link || (!moving[std::size_t(s.link)] && !moving[std::size_t(t.link)]) || allowed(s.link, t.link))
            continue;
          const double r = s.radius + t.radius + padding;
          if ((poses[std::size_t(s.link)] * s.center - poses[std::size_t(t.link)] * t.center).squaredNorm() < r * r)
            expect.insert({s.link, t.link});
        }
      const Eigen::VectorXd dir = (random_q(kin, rng) - q).normalized();
      for (const SphereCheck& got : {fast.check(q), fast.check_along(q, dir, 0.05)}) {
        if (got.pairs_overflow) {  // more pairs than a check lists
          EXPECT_GT(expect.size(), std::size_t(SphereCheck::kMaxPairs));
          ++overflow;
          continue;
        }
        if (got.proven_collision) {  // the self pass stopped at a pair whose inner balls overlap
          EXPECT_FALSE(expect.empty());
          ++proven;
          continue;
        }
        std::set<std::pair<int, int>> pairs;
        for (int k = 0; k < got.pair_count; ++k)
          pairs.insert(std::minmax(got.pairs[std::size_t(k)].first, got.pairs[std::size_t(k)].second));
        ASSERT_EQ(pairs, expect) << "configuration " << n << " on the " << to_string(path) << " path";
        EXPECT_EQ(got.self_free, expect.empty());
        kinds.insert(expect);
      }
    }
    // (This arm's wrist spheres overlap in every configuration: its self tables settle them.)
    EXPECT_GT(kinds.size(), 50u) << "random configurations fold the arm into itself in many ways";
    EXPECT_GT(proven, 0);
    EXPECT_LT(overflow, 300);
  }
}

TEST(Collision, HeldObjectIsCheckedAndMayTouchTheFingers) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  Eigen::VectorXd home(7);
  home << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  Scene scene;
  scene.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 3, 3})}});
  ExactChecker exact(kin, scene);
  const int tcp = arm.model.link_index("dmgarm_tcp");
  std::vector<int> fingers{arm.model.link_index("dmgarm_leftfinger"), arm.model.link_index("dmgarm_rightfinger")};
  // A 6 cm cube held between the fingers.
  Shape cube = box({0.06, 0.06, 0.06}, Eigen::Vector3d::Zero());
  TriMesh mesh = [&] {
    TriMesh m;
    m.vertices.resize(8, 3);
    for (int i = 0; i < 8; ++i) m.vertices.row(i) << (i & 1 ? 0.03 : -0.03), (i & 2 ? 0.03 : -0.03), (i & 4 ? 0.03 : -0.03);
    m.triangles.resize(12, 3);
    m.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5;
    return m;
  }();
  auto held = exact.with_attached(mesh, tcp, Eigen::Isometry3d::Identity(), fingers);
  EXPECT_TRUE(held.check(home).free()) << held.check(home).contact;
  // Put an obstacle where only the object is: the base checker says free, the grasp's says no.
  const Eigen::Vector3d below = kin.tip_pose(home) * Eigen::Vector3d(0, 0, 0.0);
  Scene s2 = scene;
  s2.objects.push_back({"pin", {box({0.01, 0.01, 0.01}, below + Eigen::Vector3d(0, 0, -0.025))}});
  ExactChecker e2(kin, s2);
  auto held2 = e2.with_attached(mesh, tcp, Eigen::Isometry3d::Identity(), fingers);
  EXPECT_FALSE(held2.is_free(home));
  EXPECT_NE(held2.check(home).contact.find("held object"), std::string::npos);
  (void)cube;
}

namespace {
// `count` boxes, cylinders and spheres (in turn) of random sizes (up to 0.1 + `spread` m),
// places in [-1, 1]^3 and orientations.
Scene random_primitives(std::mt19937_64& rng, int count, double spread) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> g(0, 1);
  Scene scene;
  for (int k = 0; k < count; ++k) {
    Shape s = box(Eigen::Vector3d(0.1 + spread * std::abs(u(rng)), 0.1 + spread * std::abs(u(rng)), 0.05 + spread * std::abs(u(rng))),
                  Eigen::Vector3d(u(rng), u(rng), u(rng)));
    s.type = k % 3 == 0 ? ShapeType::Box : k % 3 == 1 ? ShapeType::Cylinder : ShapeType::Sphere;
    if (s.type != ShapeType::Box) s.size.z() = 0;
    s.origin.linear() = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    scene.objects.push_back({"o" + std::to_string(k), {s}});
  }
  return scene;
}
}  // namespace

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
      const auto hit = std::find_if(out.begin(), out.end(), [&](const auto& s) { return std::abs(s.distance - distance[k]) < 1e-9; });
      ASSERT_NE(hit, out.end()) << "primitive " << k << " at " << distance[k] << " is not listed";
      ++listed;
      // Points of the solid: random in its bounding box, kept where the shape's distance says inside.
      const Shape& s = scene.objects[k].shapes[0];
      for (int m = 0; m < 200; ++m) {
        const Eigen::Vector3d y = s.origin * Eigen::Vector3d(u(rng) * s.size.x(), u(rng) * s.size.x(), u(rng) * std::max(s.size.x(), s.size.y()));
        if (shape_signed_distance(s, y) > 0) continue;
        ASSERT_GE(hit->normal.dot(p - y), hit->distance - 1e-9) << "primitive " << k << ", p = " << p.transpose();
      }
    }
    EXPECT_LE(out.size(), std::size_t(std::count_if(distance.begin(), distance.end(), [&](double d) { return d < within; })));
  }
  EXPECT_GT(listed, 300);
  EXPECT_GT(inside, 10);
}

// The certified free distance is a proof: every configuration within it along the direction is
// free for FCL (random directions and random points of the certified stretch), self-distance
// tables included.
TEST_P(FastLayer, CertifiedFreeDistanceIsFreeForFclAlongTheWholeStretch) {
  ShelfWorld w;
  const auto& [arm, kin, scene, sdf] = w;
  SphereFieldChecker fast = make(w);
  fast.set_self_tables(test::self_distance_tables(kin, arm.spheres));
  ExactChecker exact(kin, scene);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 1);
  int certified = 0;
  double longest = 0;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::VectorXd q = random_q(kin, rng);
    Eigen::VectorXd dir(kin.dof());
    for (int j = 0; j < kin.dof(); ++j) dir[j] = g(rng);
    dir.normalize();
    const SphereCheck c = fast.check_along(q, dir);
    EXPECT_EQ(c.free(), fast.check(q).free());
    if (!c.free()) continue;
    ASSERT_GE(c.free_distance, 0.0);
    // A caller that needs less gets a cheaper certificate: at least what it asked for (or all
    // there is), and just as sound.
    const double enough = std::uniform_real_distribution<double>(0.0, 0.05)(rng);
    const double limited = fast.check_along(q, dir, enough).free_distance;
    EXPECT_GE(limited, std::min(enough, c.free_distance) - 1e-12);
    EXPECT_LE(limited, c.free_distance + 1e-12) << "less work cannot prove more";
    if (c.free_distance <= 0) continue;
    ++certified;
    longest = std::max(longest, std::min(c.free_distance, 10.0));
    // Walk both ways in 2 mrad steps to the first FCL contact (or the joint limits): the
    // certificates must stop short of it.
    for (const double certificate : {c.free_distance, limited})
      for (const double sign : {1.0, -1.0}) {
        for (double t = 0.002; t <= std::min(certificate, 3.0); t += 0.002) {
          const Eigen::VectorXd x = q + sign * t * dir;
          if (!kin.within_limits(x)) break;  // beyond the limits nothing is claimed
          ASSERT_TRUE(exact.is_free(x)) << "certified " << certificate << " from q = " << q.transpose() << " but "
                                        << exact.check(x).contact << " at t = " << sign * t;
        }
      }
  }
  EXPECT_GT(certified, 100) << "the certificate must be non-trivial in free space";
  EXPECT_GT(longest, 0.02);
  RecordProperty("certified", certified);
}

// Every check and span batch of one motion shares its direction's static speeds (kept per thread,
// SphereFieldChecker::static_speeds). A checker and its per-grasp copy (more bodies and pairs),
// asked in turn along one direction, must each answer as when asked alone.
TEST_P(FastLayer, CheckersAskedInTurnAlongOneDirectionAnswerAsAlone) {
  ShelfWorld w;
  const auto& [arm, kin, scene, sdf] = w;
  SphereFieldChecker fast = make(w);
  fast.set_self_tables(test::self_distance_tables(kin, arm.spheres));
  AttachedSpheres object;  // a 12 cm rod held along the tool axis
  object.link = arm.model.link_index("dmgarm_tcp");
  for (int k = 0; k < 4; ++k) {
    object.centers.emplace_back(0, 0, 0.03 + 0.03 * k);
    object.radii.push_back(0.03);
  }
  object.touching_links = {arm.model.link_index("dmgarm_leftfinger"), arm.model.link_index("dmgarm_rightfinger")};
  const SphereFieldChecker held = fast.with_attached(object);
  std::mt19937_64 rng(21);
  std::normal_distribution<double> g(0, 1);
  auto unit = [&] {
    Eigen::VectorXd d(kin.dof());
    for (int j = 0; j < kin.dof(); ++j) d[j] = g(rng);
    return Eigen::VectorXd(d.normalized());
  };
  int differ = 0, proven = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::VectorXd q = random_q(kin, rng), dir = unit(), other = unit();
    const Eigen::VectorXd far = q + 0.02 * dir;
    const double* lanes[2] = {q.data(), far.data()};
    // Alone: another direction asked just before. A certificate asked to last `enough` reads the
    // static speeds for what it may skip; a span batch widens by them.
    const double enough = 0.03;
    (void)fast.check_along(q, other, enough);
    const double held_alone = held.check_along(q, dir, enough).free_distance;
    (void)fast.check_along(q, other, enough);
    const double base_alone = fast.check_along(q, dir, enough).free_distance;
    (void)fast.check_along(q, other, enough);
    const std::uint32_t held_lanes_alone = held.free_lanes_along(lanes, 2, dir, 0.01);
    // In turn, the same direction throughout.
    const double base = fast.check_along(q, dir, enough).free_distance;
    const double with_object = held.check_along(q, dir, enough).free_distance;
    const std::uint32_t held_lanes = held.free_lanes_along(lanes, 2, dir, 0.01);
    const double base_again = fast.check_along(q, dir, enough).free_distance;
    EXPECT_EQ(base, base_alone);
    EXPECT_EQ(base_again, base_alone);
    EXPECT_EQ(with_object, held_alone);
    EXPECT_EQ(held_lanes, held_lanes_alone);
    differ += base_alone != held_alone;
    proven += held_alone > 0;
  }
  EXPECT_GT(differ, 3) << "the held object must change some certificates";
  EXPECT_GT(proven, 50);
}

// The two layers share one set of link poses per query, so they must pose the same robot.
TEST(TwoLayer, RefusesLayersOnDifferentKinematics) {
  ShelfWorld w;
  Kinematics other(w.arm.model, "dmgarm_link0", "dmgarm_tcp");
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  EXPECT_THROW(TwoLayerChecker(fast, ExactChecker(other, w.scene)), Error);
  EXPECT_NO_THROW(TwoLayerChecker(fast, ExactChecker(w.kin, w.scene)));
}

// Sharper than FCL for the scene: with exact primitives the fast layer's environment answer is
// exact for its spheres, so along a certificate every sphere must stay clear of the scene (what
// the speed bounds, static, Gronwall and Taylor, promise, with no slack from the spheres' excess
// over the meshes), directional ones included (spheres sliding along the board and the wall: a
// share of the certificates must be a quarter past their isotropic estimate or more). Self-collision, partly
// settled by tables, is checked by FCL.
TEST(Certificate, KeepsEverySphereClearOfTheSceneAlongTheStretch) {
  ShelfWorld w;
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  fast.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  ExactChecker exact(w.kin, w.scene);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1);
  int certified = 0, directional = 0;
  double longest = 0;
  auto clear = [&](const Eigen::VectorXd& x) { return fast.check(x).environment_free && exact.is_free(x); };
  for (int i = 0; i < 3000; ++i) {
    const Eigen::VectorXd q = random_q(w.kin, rng);
    Eigen::VectorXd dir(w.kin.dof());
    for (int j = 0; j < w.kin.dof(); ++j) dir[j] = g(rng);
    dir.normalize();
    const SphereCheck c = fast.check_along(q, dir);
    // Near the scene, where certificates are short and every bound counts.
    if (!c.free() || c.free_distance <= 0 || c.min_clearance > 0.03) continue;
    ++certified;
    EXPECT_LE(c.isotropic_distance, c.free_distance);
    if (c.free_distance > 1.25 * c.isotropic_distance) ++directional;
    const double step = std::min(0.001, c.free_distance / 20);
    for (const double sign : {1.0, -1.0}) {
      double t = step;
      for (; t <= std::min(c.free_distance, 1.0); t += step) {
        const Eigen::VectorXd x = q + sign * t * dir;
        if (!w.kin.within_limits(x)) break;
        ASSERT_TRUE(clear(x)) << "certified " << c.free_distance << " from q = " << q.transpose() << " along "
                              << (sign * dir).transpose() << " but a sphere touches the scene at t = " << t;
      }
    }
    longest = std::max(longest, c.free_distance);
  }
  EXPECT_GT(certified, 100);
  EXPECT_GT(longest, 0.02);
  EXPECT_GT(directional, 20) << "of " << certified;
  RecordProperty("certified", certified);
  RecordProperty("directional", directional);
}

// The same for the whole robot, self pairs included (FCL judges), and for the callers that need
// only so much (`enough`): a pair's gap limits the certificate, and sphere pairs farther apart
// than the gap or than `need` are skipped, so those skips must keep it valid.
TEST(Certificate, KeepsTheRobotClearOfItselfAndTheSceneForEveryEnough) {
  ShelfWorld w;
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  fast.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  ExactChecker exact(w.kin, w.scene);
  std::mt19937_64 rng(17);
  int certified = 0;
  for (int i = 0; i < 400; ++i) {
    // Where it matters: a little joint motion (0.15 rad) short of a collision, heading for it.
    const Eigen::VectorXd a = random_q(w.kin, rng), b = random_q(w.kin, rng);
    if (!exact.is_free(a) || exact.is_free(b)) continue;
    double lo = 0, hi = 1;
    for (int k = 0; k < 30; ++k) (exact.is_free(a + (lo + hi) / 2 * (b - a)) ? lo : hi) = (lo + hi) / 2;
    const Eigen::VectorXd dir = (b - a).normalized();
    const Eigen::VectorXd q = a + lo * (b - a) - 0.15 * dir;
    if (!w.kin.within_limits(q)) continue;
    for (const double enough : {std::numeric_limits<double>::infinity(), 0.2, 0.05}) {
      const SphereCheck c = fast.check_along(q, dir, enough);
      if (!c.free() || c.free_distance <= 0) continue;
      ++certified;
      const double reach = std::min(c.free_distance, 1.0), step = std::min(reach / 40, 0.002);
      for (const double sign : {1.0, -1.0})
        for (double t = step; t <= reach; t += step) {
          const Eigen::VectorXd x = q + sign * t * dir;
          if (!w.kin.within_limits(x)) break;
          ASSERT_TRUE(exact.is_free(x)) << "certified " << c.free_distance << " (enough " << enough << ") from q = "
                                        << q.transpose() << " along " << (sign * dir).transpose() << " but t = " << t
                                        << " collides";
        }
    }
  }
  EXPECT_GT(certified, 100);
}

// The field stops at its band: far from every obstacle a body's certificate comes from its
// bounding sphere against the exact primitives, not from the band's "at least 0.3 m". Turning the
// base with a box 3 m away, the certificate is never shorter than the field's alone, 1.5x longer
// in the median (then the base link's pairs limit it; 1.0x before), and free for FCL.
TEST(Certificate, FarFromTheSceneTheFieldsBandDoesNotCapIt) {
  const Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  kin.set_joint_value("dmgarm_finger_joint1", 0.03);
  Scene scene;
  scene.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 0, 0.5})}});
  const double band = 0.3;
  SphereFieldChecker field_only(
      kin, arm.spheres, test::analytic_sdf(scene, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, band),
      band);
  field_only.set_self_tables(test::self_distance_tables(kin, arm.spheres));
  SphereFieldChecker fast = field_only;
  fast.set_exact_obstacles(PrimitiveObstacles::from_scene(scene));
  ExactChecker exact(kin, scene);
  Eigen::VectorXd base_turn = Eigen::VectorXd::Zero(kin.dof());
  base_turn[0] = 1;
  std::mt19937_64 rng(5);
  std::vector<double> with_exact, with_field;
  for (int i = 0; i < 300; ++i) {
    const Eigen::VectorXd q = random_q(kin, rng);
    const SphereCheck c = fast.check_along(q, base_turn);
    if (!c.free()) continue;
    const double field = field_only.check_along(q, base_turn).free_distance;
    EXPECT_GE(c.free_distance, field - 1e-12) << "q = " << q.transpose();
    with_exact.push_back(c.free_distance);
    with_field.push_back(field);
    if (with_exact.size() > 40) continue;
    for (const double sign : {1.0, -1.0})
      for (double t = 0.005; t <= std::min(c.free_distance, 1.5); t += 0.005) {
        const Eigen::VectorXd x = q + sign * t * base_turn;
        if (!kin.within_limits(x)) break;
        ASSERT_TRUE(exact.is_free(x)) << "certified " << c.free_distance << " from q = " << q.transpose() << " but "
                                      << exact.check(x).contact << " at t = " << sign * t;
      }
  }
  ASSERT_GT(with_exact.size(), 100u);
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  EXPECT_GT(median(with_exact), 1.5 * median(with_field));
}

// Where the spheres flag links (near the scene, pairs close), exact clearances certify the state
// (TwoLayerChecker::free_distance): never a collision, and every certified stretch free for FCL.
TEST(TwoLayer, ExactGapCertificatesKeepEveryStateFree) {
  ShelfWorld w;
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  fast.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  const ExactChecker exact(w.kin, w.scene);
  ASSERT_TRUE(exact.gaps_are_cheap()) << "the built-in arm and the shelf are primitives: gaps on by default";
  const TwoLayerChecker both(fast, exact);
  double longest = 0;
  const int walked = test::walk_gap_certificates(both, exact, 3000, 17, &longest);
  EXPECT_GT(walked, 50) << "flagged states must get exact certificates";
  EXPECT_GT(longest, 0.01);
  RecordProperty("walked", walked);
}

// link_time and pair_time (the exact layer's certificates, from the speed bounds check_along uses)
// hold for every point of a link's spheres: within the time given for a gap, no point moves that
// far, and no point of one link changes its distance to a point of the other by that much. Gaps
// of 2-20 mm keep the times short, where the bounds are tight: a lever arm taken too short, or a
// joint left out, shows here (halving the arms fails it).
TEST(Certificate, LinkAndPairTimesKeepEveryPointWithinTheGap) {
  ShelfWorld w;
  const SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  std::mt19937_64 rng(23);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  // Per link: its spheres' centres and points on their surfaces (link frame).
  std::vector<std::vector<Eigen::Vector3d>> points(w.kin.model().links.size());
  for (const auto& sp : w.arm.spheres) {
    points[std::size_t(sp.link)].push_back(sp.center);
    for (int k = 0; k < 6; ++k) points[std::size_t(sp.link)].push_back(sp.center + sp.radius * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  }
  const auto moving = w.kin.moving_links();
  std::vector<int> links;
  for (std::size_t l = 0; l < points.size(); ++l)
    if (moving[l] && !points[l].empty()) links.push_back(int(l));
  ASSERT_GE(links.size(), 5u);
  auto world = [&](const Eigen::VectorXd& x, int link) {
    std::vector<Eigen::Isometry3d> poses;
    w.kin.link_poses(x, poses);
    std::vector<Eigen::Vector3d> out;
    for (const auto& p : points[std::size_t(link)]) out.push_back(poses[std::size_t(link)] * p);
    return out;
  };
  int link_cases = 0, pair_cases = 0;
  double tightest = 0;  // the largest share of the gap any point used
  for (int trial = 0; trial < 600; ++trial) {
    const Eigen::VectorXd q = random_q(w.kin, rng);
    Eigen::VectorXd dir(w.kin.dof());
    for (int j = 0; j < w.kin.dof(); ++j) dir[j] = g(rng);
    dir.normalize();
    std::vector<Eigen::Isometry3d> poses;
    w.kin.link_poses(q, poses);
    const double gap = 0.002 + 0.018 * u(rng);
    const int a = links[std::size_t(rng() % links.size())], b = links[std::size_t(rng() % links.size())];
    const double tl = fast.link_time(poses, a, gap, dir);
    ASSERT_GT(tl, 0.0);
    const auto pa = world(q, a);
    for (double t = tl / 8; t <= std::min(tl, 2.0); t += tl / 8) {
      const auto xa = world(q + t * dir, a);
      for (std::size_t k = 0; k < pa.size(); ++k) {
        const double moved = (xa[k] - pa[k]).norm();
        ASSERT_LT(moved, gap) << "link " << a << " at t = " << t << " of " << tl;
        tightest = std::max(tightest, moved / gap);
      }
    }
    ++link_cases;
    const double tp = a == b ? 0.0 : fast.pair_time(poses, a, b, gap, dir);
    if (tp <= 0) continue;  // not a pair the checker tests
    const auto pb = world(q, b);
    for (double t = tp / 8; t <= std::min(tp, 2.0); t += tp / 8) {
      const auto xa = world(q + t * dir, a), xb = world(q + t * dir, b);
      for (std::size_t i = 0; i < pa.size(); ++i)
        for (std::size_t j = 0; j < pb.size(); ++j)
          ASSERT_LT(std::abs((xa[i] - xb[j]).norm() - (pa[i] - pb[j]).norm()), gap) << "links " << a << ", " << b << " at t = " << t;
    }
    ++pair_cases;
  }
  EXPECT_EQ(link_cases, 600);
  EXPECT_GT(pair_cases, 100);
  EXPECT_GT(tightest, 0.5) << "the bound must be close to the true motion somewhere";
  RecordProperty("tightest", std::to_string(tightest));
}

// Plain checks ask gaps for a sign only (enough = 0): it must be the full gap's sign, on random
// states of the shelf and where a bounding ball alone would pass: an obstacle just off a box's
// corner touches the box's ball there, closer than the 0.1 mm a computed gap gives up.
TEST(TwoLayer, AGapsSignQueryAgreesWithTheFullGap) {
  ShelfWorld w;
  const ExactChecker exact(w.kin, w.scene);
  std::mt19937_64 rng(23);
  std::vector<Eigen::Isometry3d> poses;
  const int links = int(w.arm.model.links.size());
  int positive = 0, other = 0;
  auto agree = [&](double sign, double full, const std::string& what) {
    ASSERT_EQ(sign > 0, full > 0) << what << ": sign query " << sign << ", full gap " << full;
    ++(full > 0 ? positive : other);
  };
  for (int n = 0; n < 300; ++n) {
    w.kin.link_poses(random_q(w.kin, rng), poses);
    for (int a = 0; a < links; ++a) {
      if (w.arm.model.links[std::size_t(a)].collision.empty()) continue;
      agree(exact.link_environment_gap(poses, a, 0.0), exact.link_environment_gap(poses, a), w.arm.model.links[std::size_t(a)].name);
      for (int b = a + 1; b < links; ++b)
        if (!w.arm.model.links[std::size_t(b)].collision.empty())
          agree(exact.link_pair_gap(poses, a, b, 0.0), exact.link_pair_gap(poses, a, b), "pair");
    }
  }
  EXPECT_GT(positive, 1000);
  EXPECT_GT(other, 100);

  const int base = w.arm.model.link_index("dmgarm_link0");
  const auto& shapes = w.arm.model.links[std::size_t(base)].collision;
  ASSERT_EQ(shapes.size(), 1u);
  ASSERT_EQ(shapes[0].type, ShapeType::Box);
  w.kin.link_poses(Eigen::VectorXd::Zero(w.kin.dof()), poses);
  const Eigen::Isometry3d pose = poses[std::size_t(base)] * shapes[0].origin;
  const Eigen::Vector3d corner = pose * Eigen::Vector3d(shapes[0].size / 2);
  const Eigen::Vector3d out = (corner - pose.translation()).normalized();
  for (const double d : {2e-5, 5e-5, 9e-5, 3e-4, 1e-2}) {
    Shape ball;
    ball.type = ShapeType::Sphere;
    ball.size = Eigen::Vector3d(0.005, 0, 0);
    ball.origin.translation() = corner + (0.005 + d) * out;
    Scene scene;
    scene.objects.push_back({"ball", {ball}});
    const ExactChecker near(w.kin, scene);
    const double full = near.link_environment_gap(poses, base), sign = near.link_environment_gap(poses, base, 0.0);
    EXPECT_EQ(full > 0, d > 1e-4) << "a gap counts only beyond 0.1 mm; " << d << " m off the corner: " << full;
    EXPECT_EQ(sign > 0, full > 0) << d << " m off the corner: sign query " << sign << ", full gap " << full;
  }
}

// links_free (links at given poses, the placement's hand check) must answer as the exact layer
// does for the same links placed by forward kinematics, one link at a time and all together.
TEST(ExactChecker, LinksFreeAtGivenPosesAgreesWithFcl) {
  ShelfWorld w;
  const ExactChecker exact(w.kin, w.scene);
  std::mt19937_64 rng(29);
  std::vector<Eigen::Isometry3d> poses;
  const int links = int(w.arm.model.links.size());
  int free = 0, colliding = 0;
  for (int n = 0; n < 400; ++n) {
    w.kin.link_poses(random_q(w.kin, rng), poses);
    std::vector<std::pair<int, Eigen::Isometry3d>> all;
    bool all_free = true;
    for (int a = 0; a < links; ++a) {
      if (w.arm.model.links[std::size_t(a)].collision.empty()) continue;
      const bool fcl = exact.links_environment_free(poses, &a, 1, false, nullptr);
      ASSERT_EQ(exact.links_free({{a, poses[std::size_t(a)]}}), fcl) << w.arm.model.links[std::size_t(a)].name << ", sample " << n;
      ++(fcl ? free : colliding);
      all_free = all_free && fcl;
      all.emplace_back(a, poses[std::size_t(a)]);
    }
    EXPECT_EQ(exact.links_free(all), all_free) << "sample " << n;
  }
  EXPECT_GT(free, 1000);
  EXPECT_GT(colliding, 100);
}

namespace {
// A UV sphere whose vertices lie at `radius` around `at`: inside the ball of that radius, and
// containing the ball of radius `radius * cos(pi / 12)` (its faces' distance from the centre).
TriMesh uv_sphere(double radius) {
  const int nu = 24, nv = 12;
  TriMesh m;
  m.vertices.resize(2 + nu * (nv - 1), 3);
  m.vertices.row(0) = Eigen::RowVector3d(0, 0, radius);
  m.vertices.row(1) = Eigen::RowVector3d(0, 0, -radius);
  for (int v = 1; v < nv; ++v)
    for (int u = 0; u < nu; ++u) {
      const double th = M_PI * v / nv, ph = 2 * M_PI * u / nu;
      m.vertices.row(2 + (v - 1) * nu + u) =
          radius * Eigen::RowVector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  std::vector<Eigen::RowVector3i> t;
  auto at = [&](int v, int u) { return 2 + (v - 1) * nu + (u % nu); };
  for (int u = 0; u < nu; ++u) {
    t.emplace_back(0, at(1, u), at(1, u + 1));
    t.emplace_back(1, at(nv - 1, u + 1), at(nv - 1, u));
    for (int v = 1; v + 1 < nv; ++v) {
      t.emplace_back(at(v, u), at(v + 1, u), at(v + 1, u + 1));
      t.emplace_back(at(v, u), at(v + 1, u + 1), at(v, u + 1));
    }
  }
  m.triangles.resize(Eigen::Index(t.size()), 3);
  for (std::size_t i = 0; i < t.size(); ++i) m.triangles.row(Eigen::Index(i)) = t[i];
  return m;
}
}  // namespace

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
  double worst = 0;  // largest error seen, as a share of the bound
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
          const Eigen::Vector3d p = k == 0 && i % 50 == 0 ? Eigen::Vector3d(limit, -limit, limit)
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

// PrimitiveObstacles::clear_reaching_lanes, a body's bounding sphere in the batch check: its
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
      ASSERT_EQ(prims->clear_lanes(x, y, z, need, alive, reach), got) << "the reached primitives alone decide otherwise";
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
    EXPECT_FALSE(exact.mesh_free(CollisionMesh(uv_sphere(1.03 * d / cos_face)), at)) << p.transpose() << " distance " << d;
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

// Every sphere's inner ball lies inside its link's geometry: points on and in the ball (Fibonacci
// directions at three depths) are inside by the winding number or the primitive's distance.
TEST(SphereCover, InnerBallsLieInsideTheLinkGeometry) {
  Arm arm = built_in_arm();
  int with_ball = 0;
  for (const auto& s : arm.spheres) {
    const auto& shapes = arm.model.links[std::size_t(s.link)].collision;
    const double r = inner_radius(shapes, s.center);
    ASSERT_GE(r, 0.0);
    if (r <= 0) continue;
    ++with_ball;
    for (int k = 0; k < 64; ++k)
      for (const double depth : {0.999, 0.7, 0.3}) {
        const double z = 1 - 2 * (k + 0.5) / 64, ph = k * M_PI * (3 - std::sqrt(5.0));
        const Eigen::Vector3d x =
            s.center + depth * r * Eigen::Vector3d(std::sqrt(1 - z * z) * std::cos(ph), std::sqrt(1 - z * z) * std::sin(ph), z);
        bool inside = false;
        for (const auto& sh : shapes)
          inside |= sh.type == ShapeType::Mesh ? winding_number(sh.mesh, sh.origin.inverse() * x) > 0.5
                                               : shape_signed_distance(sh, x) <= 0;
        ASSERT_TRUE(inside) << arm.model.links[std::size_t(s.link)].name << " ball " << r << " at " << s.center.transpose();
      }
  }
  EXPECT_GT(with_ball, int(arm.spheres.size()) / 2) << "most sphere centres lie inside their link";
}
