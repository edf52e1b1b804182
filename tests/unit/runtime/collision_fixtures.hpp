#pragma once
// Shared by the built-in arm's collision tests (collision_{fast_layer,lanes,self,held_object,
// certificate}_test.cpp, exact_checker_test.cpp, primitive_obstacles_test.cpp,
// sphere_cover_test.cpp): the arm, the shelf scene, the fast layer's forms, lanes of random
// configurations and the checkers that judge them, random primitive scenes, a UV sphere.
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <random>
#include <vector>

#include "analytic_sdf.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "fixtures.hpp"
#include "test_support.hpp"

namespace dmgplace::test::collision {

struct Arm {
  RobotModel model;
  std::vector<formats::LinkSphere> spheres;
};

// The built-in arm (datasets/robots/dmgarm) and its spheres.
Arm built_in_arm();

// test::box_shape: a box of `size` centered at `at`.
Shape box(const Eigen::Vector3d& size, const Eigen::Vector3d& at);

// A board, a wall behind it, a can on the board and a ball above: four primitives within reach.
Scene shelf_scene();

// The built-in arm (fingers half open) among the shelf scene's primitives, with their 2 cm field.
struct ShelfWorld {
  Arm arm = built_in_arm();
  runtime::Kinematics kin{arm.model, "dmgarm_link0", "dmgarm_tcp"};
  Scene scene = shelf_scene();
  std::shared_ptr<runtime::Grid3> sdf = test::analytic_sdf(
      scene, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, 0.3);
  ShelfWorld() { kin.set_joint_value("dmgarm_finger_joint1", 0.03); }
};

// 8 random configurations (and their pointers, as free_lanes takes them) and a random unit
// direction (from n, which keeps its spare draw between lane checks), drawn in that order.
struct RandomLanes {
  std::vector<Eigen::VectorXd> qs;
  const double* ptr[runtime::LinkPoseLanesD::kLanes];
  Eigen::VectorXd u;
  RandomLanes(const runtime::Kinematics& kin, std::mt19937_64& rng, std::normal_distribution<double>& n);
  RandomLanes(const RandomLanes&) = delete;  // ptr points into qs
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
  runtime::SphereFieldChecker fast{w.kin, w.arm.spheres, w.sdf, 0.3};
  runtime::SphereFieldChecker held, primitives, held_primitives;
  runtime::ExactChecker exact{w.kin, w.scene};
  runtime::AttachedSpheres object;
  std::shared_ptr<const runtime::PrimitiveObstacles> scene = runtime::PrimitiveObstacles::from_scene(w.scene);
  explicit AlongCheckers(bool tables);
  std::array<const runtime::SphereFieldChecker*, 3> all() const { return {&fast, &held, &primitives}; }
  bool judge(const runtime::SphereFieldChecker* checker, const Eigen::VectorXd& q) const;
  bool sphere_judge(const runtime::SphereFieldChecker* checker, const Eigen::VectorXd& q) const;
};

// `count` boxes, cylinders and spheres (in turn) of random sizes (up to 0.1 + `spread` m),
// places in [-1, 1]^3 and orientations.
Scene random_primitives(std::mt19937_64& rng, int count, double spread);

// A UV sphere whose vertices lie at `radius` around `at`: inside the ball of that radius, and
// containing the ball of radius `radius * cos(pi / 12)` (its faces' distance from the center).
TriMesh uv_sphere(double radius);

}  // namespace dmgplace::test::collision

// Every form of the fast layer: the field alone; a scene of a few exact primitives, checked by
// their exact distances alone, with a field beside them or built without one; and one of more
// than 64, where the field goes first and the primitives settle what it leaves undecided (here
// the shelf plus 64 specks far out of reach, so the answers are the shelf's).
enum class Form { FieldOnly, WithExactPrimitives, ExactPrimitivesNoField, FieldWithManyPrimitives };
class FastLayer : public ::testing::TestWithParam<Form> {
 protected:
  dmgplace::runtime::SphereFieldChecker make(const dmgplace::test::collision::ShelfWorld& w) const;
  bool exact_primitives() const { return GetParam() != Form::FieldOnly; }
};
