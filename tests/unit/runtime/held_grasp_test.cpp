// The grasp held, measured on the mesh: the width between the fingers along the closing axis and
// the TCP's distance from the surface, against a box whose answers are known.
#include <gtest/gtest.h>

#include <random>

#include "dmgplace/runtime/grasp/held_grasp.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {
// Axis-aligned box centered at the origin, triangles counter-clockwise from outside.
TriMesh box(const Eigen::Vector3d& size) {
  TriMesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    m.vertices.row(i) = Eigen::Vector3d((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(),
                                        (i & 4 ? 0.5 : -0.5) * size.z());
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3,
      7, 5;
  return m;
}
}  // namespace

TEST(HeldGrasp, WidthAlongTheClosingAxisIsTheBoxExtentThroughTheTcp) {
  const TriMesh m = box(Eigen::Vector3d(0.10, 0.06, 0.04));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  for (int k = 0; k < 100; ++k) {
    // The TCP anywhere inside the box, its closing axis (y) along one of the box's axes.
    const int axis = k % 3;
    const Eigen::Vector3d extent(0.10, 0.06, 0.04);
    const Eigen::Vector3d p(u(rng) * 0.10, u(rng) * 0.06, u(rng) * 0.04);
    Eigen::Matrix3d r;
    const Eigen::Vector3d y = Eigen::Vector3d::Unit(axis), z = Eigen::Vector3d::Unit((axis + 1) % 3);
    r << y.cross(z), y, z;
    Eigen::Isometry3d tcp = Eigen::Translation3d(p) * Eigen::Quaterniond(r);
    const auto w = grasp_width(m, tcp);
    ASSERT_TRUE(w.has_value());
    EXPECT_NEAR(*w, extent[axis], 1e-12);
  }
}

TEST(HeldGrasp, ALineThatMissesTheObjectHasNoWidth) {
  const TriMesh m = box(Eigen::Vector3d(0.10, 0.06, 0.04));
  Eigen::Isometry3d outside = Eigen::Isometry3d::Identity();
  outside.translation() = Eigen::Vector3d(0.2, 0, 0);  // closing axis y passes beside the box
  EXPECT_FALSE(grasp_width(m, outside).has_value());
  Eigen::Isometry3d beyond = Eigen::Isometry3d::Identity();
  beyond.translation() = Eigen::Vector3d(0, 0.1, 0);  // the box lies on one side only
  EXPECT_FALSE(grasp_width(m, beyond).has_value());
}

TEST(HeldGrasp, SurfaceDistanceAgreesWithTheBoxFormula) {
  const TriMesh m = box(Eigen::Vector3d(0.10, 0.06, 0.04));
  const Eigen::Vector3d half(0.05, 0.03, 0.02);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const Eigen::Vector3d q = p.cwiseAbs() - half;
    const double outside = q.cwiseMax(0.0).norm(), inside = -std::min(q.maxCoeff(), 0.0);
    EXPECT_NEAR(surface_distance(m, p), outside > 0 ? outside : inside, 1e-12);
  }
}
