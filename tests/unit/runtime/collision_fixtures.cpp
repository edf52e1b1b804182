#include "collision_fixtures.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "lane_rounds.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

namespace dmgplace::test::collision {

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

RandomLanes::RandomLanes(const Kinematics& kin, std::mt19937_64& rng, std::normal_distribution<double>& n) {
  for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) qs.push_back(random_q(kin, rng));
  for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
  u.resize(kin.dof());
  for (int i = 0; i < u.size(); ++i) u[i] = n(rng);
  u.normalize();
}

AlongCheckers::AlongCheckers(bool tables) : held(fast), primitives(fast), held_primitives(fast) {
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

bool AlongCheckers::judge(const SphereFieldChecker* checker, const Eigen::VectorXd& q) const {
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

bool AlongCheckers::sphere_judge(const SphereFieldChecker* checker, const Eigen::VectorXd& q) const {
  return (checker == &held ? held_primitives : primitives).check(q).environment_free && judge(checker, q);
}

Scene random_primitives(std::mt19937_64& rng, int count, double spread) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> g(0, 1);
  Scene scene;
  for (int k = 0; k < count; ++k) {
    Shape s = box(Eigen::Vector3d(0.1 + spread * std::abs(u(rng)), 0.1 + spread * std::abs(u(rng)),
                                  0.05 + spread * std::abs(u(rng))),
                  Eigen::Vector3d(u(rng), u(rng), u(rng)));
    s.type = k % 3 == 0 ? ShapeType::Box : k % 3 == 1 ? ShapeType::Cylinder : ShapeType::Sphere;
    if (s.type != ShapeType::Box) s.size.z() = 0;
    s.origin.linear() = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    scene.objects.push_back({"o" + std::to_string(k), {s}});
  }
  return scene;
}

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

}  // namespace dmgplace::test::collision

SphereFieldChecker FastLayer::make(const dmgplace::test::collision::ShelfWorld& w) const {
  if (GetParam() == Form::ExactPrimitivesNoField)
    return SphereFieldChecker(w.kin, w.arm.spheres, PrimitiveObstacles::from_scene(w.scene));
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
