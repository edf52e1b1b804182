// geometry/capsule.hpp and collision/kernels/sphere_capsule.hpp: the capsule holds every sphere it
// was fitted to, and the lanes' segment test never calls a point apart that is within reach,
// beyond its stated rounding.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "dmgplace/runtime/collision/kernels/sphere_capsule.hpp"
#include "dmgplace/runtime/geometry/capsule.hpp"

using dmgplace::runtime::bounding_capsule;
using dmgplace::runtime::distance_to_segment;
namespace lanes = dmgplace::runtime::lanes;
namespace kernels = dmgplace::runtime::kernels;

namespace {

Eigen::Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Vector3d v(n(rng), n(rng), n(rng));
  return v.normalized();
}

// The lane test as the AVX2 lane check runs it (fused multiply-adds) and as the portable build does.
__attribute__((target("avx2,fma"))) std::uint32_t near_fma(const float* p, const float* f, const float* d, float inv,
                                                           float reach2) {
  using lanes::load;
  using lanes::splatf;
  return lanes::bits(kernels::near_segment(load(p), load(p + 8), load(p + 16), load(f), load(f + 8), load(f + 16),
                                           load(d), load(d + 8), load(d + 16), splatf(inv), splatf(reach2)));
}
std::uint32_t near_plain(const float* p, const float* f, const float* d, float inv, float reach2) {
  using lanes::load;
  using lanes::splatf;
  return lanes::bits(kernels::near_segment(load(p), load(p + 8), load(p + 16), load(f), load(f + 8), load(f + 16),
                                           load(d), load(d + 8), load(d + 16), splatf(inv), splatf(reach2)));
}

}  // namespace

// Random clusters of spheres, long and round ones: every point on every sphere lies within the
// capsule (the far side of each along random directions), and a long cluster gets a capsule
// thinner than its bounding sphere.
TEST(Capsule, HoldsEverySphereItWasFittedTo) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1), r(0.005, 0.08);
  int thinner = 0;
  for (int round = 0; round < 500; ++round) {
    const int n = 2 + round % 7;
    const Eigen::Vector3d axis = random_unit(rng), base(u(rng), u(rng), u(rng));
    const double length = round % 2 ? 0.4 : 0.05, spread = round % 2 ? 0.03 : 0.1;
    std::vector<Eigen::Vector3d> centers;
    std::vector<double> radii;
    for (int i = 0; i < n; ++i) {
      centers.push_back(base + axis * length * u(rng) + spread * Eigen::Vector3d(u(rng), u(rng), u(rng)));
      radii.push_back(r(rng));
    }
    const auto k = bounding_capsule(centers, radii);
    ASSERT_TRUE(k.has_value());
    double bounding = 0;
    for (int i = 0; i < n; ++i)
      bounding = std::max(bounding, (centers[std::size_t(i)] - centers[0]).norm() + radii[std::size_t(i)]);
    for (int i = 0; i < n; ++i) {
      const auto& c = centers[std::size_t(i)];
      ASSERT_LE(distance_to_segment(c, k->from, k->to) + radii[std::size_t(i)], k->radius) << "sphere " << i;
      for (int s = 0; s < 50; ++s) {
        const Eigen::Vector3d p = c + radii[std::size_t(i)] * random_unit(rng);
        ASSERT_LE(distance_to_segment(p, k->from, k->to), k->radius + 1e-12);
      }
    }
    if (round % 2 && k->radius < 0.8 * (bounding + radii[0])) ++thinner;
  }
  EXPECT_GT(thinner, 200) << "long clusters should fit capsules much thinner than a sphere";
}

TEST(Capsule, NoneForTooFewCentersOrBadInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(bounding_capsule({Eigen::Vector3d(1, 2, 3)}, {0.1}).has_value());
  EXPECT_FALSE(bounding_capsule({Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(1, 2, 3)}, {0.1, 0.2}).has_value());
  EXPECT_FALSE(bounding_capsule({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(nan, 0, 0)}, {0.1, 0.1}).has_value());
  EXPECT_FALSE(bounding_capsule({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)}, {0.1, nan}).has_value());
  EXPECT_FALSE(bounding_capsule({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)}, {0.1}).has_value());
  EXPECT_TRUE(bounding_capsule({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)}, {0.1, 0.1}).has_value());
}

// The lanes' segment test against the distance in doubles: "apart" only where the exact
// distance is at least the reach less kSegmentRounding roundoffs of |p - from| + |d|, and
// "near" wherever the exact distance is within the reach (the same bound the other way
// shows it is no stub that says near everywhere). Points far out (5 m), segments short and long,
// reaches set right at the exact distance; NaN points are near. With fused products and without.
TEST(Capsule, LaneSegmentTestIsWithinItsRoundingOfTheExactDistance) {
  const bool fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  const double u = 0x1p-24;
  for (auto* test : {&near_plain, &near_fma}) {
    if (test == &near_fma && !fma) continue;
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> coord(-5, 5), len(1e-3, 0.5), side(-1, 1);
    int apart = 0, near = 0;
    for (int round = 0; round < 20000; ++round) {
      alignas(32) float p[24], f[24], d[24];
      const Eigen::Vector3d from(coord(rng), coord(rng), coord(rng));
      const Eigen::Vector3d dir = random_unit(rng) * len(rng);
      // The segment in floats, as the lanes get it: the exact distance is to ff + t df.
      const Eigen::Vector3f ff = from.cast<float>(), df = dir.cast<float>();
      double exact[8];
      std::vector<Eigen::Vector3f> pts;
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d q = k < 4 ? from + dir * (1.5 * side(rng)) + random_unit(rng) * 0.3 * std::abs(side(rng))
                                        : Eigen::Vector3d(coord(rng), coord(rng), coord(rng));
        pts.push_back(q.cast<float>());
      }
      for (int k = 0; k < 8; ++k) {
        for (int a = 0; a < 3; ++a) p[8 * a + k] = pts[std::size_t(k)][a], f[8 * a + k] = ff[a], d[8 * a + k] = df[a];
        exact[k] = distance_to_segment(pts[std::size_t(k)].cast<double>(), ff.cast<double>(),
                                       ff.cast<double>() + df.cast<double>());
      }
      // One reach for all lanes: one lane's exact distance, nudged up or down by a little.
      const double reach = exact[round % 8] * (1 + (round % 3 - 1) * 1e-6);
      const float inv = float(1.0 / df.cast<double>().squaredNorm());
      const std::uint32_t bits = test(p, f, d, inv, float(reach * reach));
      for (int k = 0; k < 8; ++k) {
        const double slack =
            kernels::kSegmentRounding * u * ((pts[std::size_t(k)] - ff).cast<double>().norm() + df.norm()) +
            2 * u * reach;
        if (bits >> k & 1) {
          ++near;
          ASSERT_LT(exact[k], reach + slack) << "near, though the exact distance is well past the reach";
        } else {
          ++apart;
          ASSERT_GE(exact[k], reach - slack) << "apart, though within reach: lane " << k << " round " << round;
        }
      }
    }
    EXPECT_GT(apart, 1000);
    EXPECT_GT(near, 1000);
    // NaN: near.
    alignas(32) float p[24], f[24] = {}, d[24];
    for (int k = 0; k < 24; ++k) p[k] = std::numeric_limits<float>::quiet_NaN(), d[k] = 1;
    EXPECT_EQ(test(p, f, d, 1.0f / 3, 1.0f), 0xFFu);
  }
}
