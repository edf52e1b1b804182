// The node-bound copy of a distance grid bounds the scene's true signed distance from both sides:
// from below (what proves a sphere free; the cell's corners at least as well as the nearest node)
// and, below the band, from above (what proves an inner ball reached by an obstacle, so a
// collision).
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "analytic_sdf.hpp"
#include "dmgplace/runtime/collision/node_bound_grid.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

TEST(NodeBoundGrid, BoundsTheTrueSignedDistanceFromBelowAndBelowTheBandFromAbove) {
  Scene scene;
  scene.objects.push_back({"box", {test::box_shape(Eigen::Vector3d(0.4, 0.3, 0.2), Eigen::Vector3d(0.2, 0.1, 0.3))}});
  scene.objects.push_back({"slab", {test::box_shape(Eigen::Vector3d(0.9, 0.03, 0.5), Eigen::Vector3d(0, -0.4, 0.2))}});
  const double band = 0.3, res = 0.02;
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.6, -0.6, -0.4), Eigen::Vector3d(0.8, 0.7, 0.9));
  const NodeBoundGrid fine(*test::analytic_sdf(scene, box, res, band), 1);
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> x(-0.7, 0.9), y(-0.7, 0.8), z(-0.5, 1.0);
  int near = 0, tight = 0, tight_below = 0;
  for (int k = 0; k < 200000; ++k) {
    const Eigen::Vector3d p(x(rng), y(rng), z(rng));  // some beyond the grid: clamped onto it
    const double truth = test::scene_signed_distance(scene, p);
    ASSERT_LE(fine.lower_bound(p), truth + 1e-9) << p.transpose();
    const double cell = fine.cell_lower_bound(p);
    ASSERT_LE(cell, truth + 1e-9) << p.transpose();
    ASSERT_GE(cell, fine.lower_bound(p)) << "the nearest node is one of the corners: " << p.transpose();
    if (truth >= band - 2 * res) continue;  // the grid's values are clamped at the band
    ++near;
    tight_below += truth - cell < 0.5 * res;
    const double upper = fine.upper_bound(p);
    ASSERT_GE(upper, truth - 1e-9) << p.transpose();
    tight += upper - truth < 0.5 * res;
  }
  // Far outside the grid (clamped onto its last cell) and NaN: still bounds, no overflow.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1e12, -1e12, 3), Eigen::Vector3d(-5, 0.1, 1e300)}) {
    const double truth = test::scene_signed_distance(scene, p);
    EXPECT_LE(fine.cell_lower_bound(p), truth) << p.transpose();
    EXPECT_GE(fine.upper_bound(p), fine.cell_lower_bound(p)) << p.transpose();
  }
  const Eigen::Vector3d nan = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(fine.upper_bound(nan) < 0) << "a NaN point proves nothing";
  EXPECT_GT(near, 20000);
  // Not loose: the corner towards the nearest surface gives nearly the value at p.
  EXPECT_GT(tight, near * 3 / 4) << tight << " of " << near << " within half a cell";
  EXPECT_GT(tight_below, near * 3 / 4) << tight_below << " of " << near << " within half a cell";
}
