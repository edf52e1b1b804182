// The object's motion in one in-hand action and where a pusher can drive it (issue 60, part 2):
// properties against exact answers on random grasps of a box and the bottle.
#include <gtest/gtest.h>

#include <random>

#include "dmgplace/runtime/collision/object_spheres.hpp"
#include "dmgplace/runtime/grasp/held_grasp.hpp"
#include "dmgplace/runtime/placement/push_geometry.hpp"
#include "fixtures.hpp"

namespace dmgplace::test {
namespace {
using runtime::object_motion;
using runtime::ObjectMotion;

Eigen::Isometry3d random_pose(std::mt19937_64& rng, double reach) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  q.normalize();
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = q.toRotationMatrix();
  p.translation() = reach * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return p;
}

TEST(PushGeometry, TheMotionTakesTheObjectFromItsPoseAtOneGraspToItsPoseAtTheOther) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Isometry3d tcp = random_pose(rng, 0.6), before = random_pose(rng, 0.05),
                            after = random_pose(rng, 0.05);
    const ObjectMotion m = object_motion(tcp, before, after);
    // The gripper holds still: the object's pose at each grasp puts the TCP where it is.
    EXPECT_TRUE((m.before * before).isApprox(tcp, 1e-12));
    EXPECT_TRUE((m.after * after).isApprox(tcp, 1e-12));
    EXPECT_TRUE((m.at(1) * m.before).isApprox(m.after, 1e-9)) << trial;
    EXPECT_TRUE(m.at(0).isApprox(Eigen::Isometry3d::Identity(), 1e-15));
    // The pivot (the TCP) moves only by the shift.
    for (double s : {0.25, 0.5, 0.75}) EXPECT_LT((m.at(s) * m.pivot - m.pivot - s * m.shift).norm(), 1e-12);
    // velocity() is the derivative of at() for a point carried by the object.
    const Eigen::Vector3d x = m.pivot + Eigen::Vector3d(0.03, -0.02, 0.05);
    for (double s : {0.0, 0.4, 0.9}) {
      const double h = 1e-6;
      const Eigen::Vector3d numeric = (m.at(s + h) * x - m.at(s - h) * x) / (2 * h);
      EXPECT_LT((numeric - m.velocity(x, s)).norm(), 1e-6) << trial << " s " << s;
    }
  }
}

TEST(PushGeometry, ContactsLieOnTheSurfaceAndPushIntoIt) {
  std::mt19937_64 rng(7);
  for (const TriMesh& mesh : {box_mesh(Eigen::Vector3d(0.13, 0.05, 0.035)), bottle_mesh()}) {
    int with_contacts = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const Eigen::Isometry3d tcp = random_pose(rng, 0.5);
      // A slide (grasp moved along the object) or a turn about the grasp axis (y).
      Eigen::Isometry3d before = Eigen::Isometry3d::Identity(), after = before;
      if (trial % 2) after.translation() = Eigen::Vector3d(0.02, 0, 0.01);
      else after.linear() = Eigen::AngleAxisd(0.3 + 0.05 * trial, Eigen::Vector3d::UnitY()).toRotationMatrix();
      const ObjectMotion m = object_motion(tcp, before, after);
      const auto contacts = runtime::push_contacts(mesh, m, 8, 0.01);
      with_contacts += !contacts.empty();
      for (std::size_t i = 0; i < contacts.size(); ++i) {
        const auto& c = contacts[i];
        // On the surface of the object at its pose before the action.
        EXPECT_LT(runtime::surface_distance(mesh, m.before.inverse() * c.point), 1e-9);
        // Pushing along the point's own velocity, which goes into the object: a little way along it
        // the point is inside, a little way back it is outside.
        EXPECT_LT((c.direction - m.velocity(c.point, 0).normalized()).norm(), 1e-12);
        // (Off the mesh's seams by a hair: the parity test's axis rays must not run along an edge.)
        const Eigen::Vector3d hair(3e-7, 5e-7, 7e-7);
        EXPECT_TRUE(runtime::inside_mesh(mesh, m.before.inverse() * (c.point + 1e-4 * c.direction) + hair)) << trial;
        EXPECT_FALSE(runtime::inside_mesh(mesh, m.before.inverse() * (c.point - 1e-4 * c.direction) + hair)) << trial;
        if (i > 0) EXPECT_LE(c.score, contacts[i - 1].score);
        for (std::size_t j = 0; j < i; ++j) EXPECT_GE((c.point - contacts[j].point).norm(), 0.01);
      }
    }
    EXPECT_GT(with_contacts, 30);
  }
}

}  // namespace
}  // namespace dmgplace::test
