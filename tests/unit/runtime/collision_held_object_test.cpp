// Held objects: checkers with an attached mesh, built while other threads check.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "collision_fixtures.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using namespace dmgplace::test::collision;

// Per-query checkers build FCL objects over the world's shared meshes while other queries run,
// and FCL's object constructor rewrites its geometry's bounds (a mesh's radius passes through 0
// and its square). A rod whose only contact is at its far end is found every time, however many
// checkers other threads build over the same mesh meanwhile.
TEST(Collision, MeshChecksHoldWhileOtherThreadsBuildCheckersOverTheSameMesh) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  Eigen::VectorXd home(7);
  home << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  // A 1 m rod along x; many copies of its center after the corners make FCL's bound loops long.
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
    for (int i = 0; i < 8; ++i)
      m.vertices.row(i) << (i & 1 ? 0.03 : -0.03), (i & 2 ? 0.03 : -0.03), (i & 4 ? 0.03 : -0.03);
    m.triangles.resize(12, 3);
    m.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3,
        7, 5;
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
