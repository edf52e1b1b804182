#include <gtest/gtest.h>

#include <random>

#include "dmgplace/runtime/geometry/grid3.hpp"

using dmgplace::runtime::Grid3;

namespace {
// An affine field is reproduced exactly by trilinear interpolation.
double affine(const Eigen::Vector3d& p) { return 0.3 + 2.0 * p.x() - 1.5 * p.y() + 0.25 * p.z(); }

Grid3 filled(double (*f)(const Eigen::Vector3d&)) {
  Grid3 g(Eigen::Vector3d(-0.5, 0.1, 2.0), 0.05, {21, 13, 9});
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 13; ++j)
      for (int i = 0; i < 21; ++i) g.values()[g.index(i, j, k)] = float(f(g.point(i, j, k)));
  return g;
}
}  // namespace

TEST(Grid3, AffineFieldIsReproducedWithExactGradient) {
  Grid3 g = filled(affine);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(-0.5, 0.5), uy(0.1, 0.7), uz(2.0, 2.4);
  for (int n = 0; n < 1000; ++n) {
    Eigen::Vector3d p(ux(rng), uy(rng), uz(rng)), grad;
    EXPECT_NEAR(g.sample(p, grad), affine(p), 1e-5);
    EXPECT_NEAR(grad.x(), 2.0, 1e-4);
    EXPECT_NEAR(grad.y(), -1.5, 1e-4);
    EXPECT_NEAR(grad.z(), 0.25, 1e-4);
  }
}

TEST(Grid3, GradientMatchesFiniteDifferencesOfNonlinearField) {
  Grid3 g = filled([](const Eigen::Vector3d& p) { return std::sin(3 * p.x()) * std::cos(2 * p.y()) + p.z() * p.z(); });
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(-0.45, 0.45), uy(0.15, 0.65), uz(2.05, 2.35);
  const double h = 1e-6;
  for (int n = 0; n < 500; ++n) {
    Eigen::Vector3d p(ux(rng), uy(rng), uz(rng)), grad;
    g.sample(p, grad);
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d e = Eigen::Vector3d::Unit(a) * h;
      double fd = (g.sample(p + e) - g.sample(p - e)) / (2 * h);
      EXPECT_NEAR(grad[a], fd, 1e-3 * (1 + std::abs(fd)));
    }
  }
}

TEST(Grid3, SamplesAtNodesAndClampsOutside) {
  Grid3 g = filled(affine);
  EXPECT_FLOAT_EQ(float(g.sample(g.point(3, 4, 5))), g.at(3, 4, 5));
  Eigen::Vector3d grad;
  const double far = g.sample(Eigen::Vector3d(-10, 0.3, 2.2), grad);
  EXPECT_NEAR(far, g.sample(Eigen::Vector3d(-0.5, 0.3, 2.2)), 1e-9);
  EXPECT_EQ(grad.x(), 0.0);
  EXPECT_TRUE(std::isfinite(g.sample(Eigen::Vector3d(NAN, 0.3, 2.2))));
  EXPECT_THROW(Grid3(Eigen::Vector3d::Zero(), 0.0, {2, 2, 2}), std::invalid_argument);
}
