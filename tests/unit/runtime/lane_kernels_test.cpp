// The lane check's lane kernels (runtime/collision/kernels/), each against an exact answer in
// doubles: where the float answer may differ is only within the rounding the callers' margins
// cover.
#include <gtest/gtest.h>

#include <random>

#include "analytic_sdf.hpp"
#include "dmgplace/runtime/collision/kernels/lane_points.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_box.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_cylinder.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_field.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_sphere.hpp"
#include "dmgplace/runtime/collision/kernels/table_lookup.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {
constexpr int N = LinkPoseLanesD::kLanes;

LaneXyz random_points(std::mt19937_64& rng, double extent) {
  std::uniform_real_distribution<double> u(-extent, extent);
  LaneXyz p;
  for (int k = 0; k < N; ++k) p.x[k] = float(u(rng)), p.y[k] = float(u(rng)), p.z[k] = float(u(rng));
  return p;
}
Eigen::Vector3d lane(const LaneXyz& p, int k) { return {p.x[k], p.y[k], p.z[k]}; }
std::uint32_t bits(lanes::MF m) { return lanes::bits(m); }
}  // namespace

TEST(LaneKernels, TransformIsTheRigidMotionToFloatRounding) {
  std::mt19937_64 rng(3);
  for (int round = 0; round < 200; ++round) {
    kernels::LinkPose pose;
    std::array<Eigen::Isometry3d, N> T;
    for (int k = 0; k < N; ++k) {
      T[std::size_t(k)] = Eigen::Translation3d(Eigen::Vector3d::Random()) * Eigen::Quaterniond::UnitRandom();
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
          pose[std::size_t(3 * r + c)][std::size_t(k)] = float(T[std::size_t(k)].linear()(r, c));
        pose[std::size_t(9 + r)][std::size_t(k)] = float(T[std::size_t(k)].translation()[r]);
      }
    }
    const LaneXyz p = random_points(rng, 0.3);
    LaneXyz out;
    kernels::transform(kernels::PoseLanes(pose), lanes::load(p.x), lanes::load(p.y), lanes::load(p.z), out);
    for (int k = 0; k < N; ++k) EXPECT_LT((lane(out, k) - T[std::size_t(k)] * lane(p, k)).norm(), 1e-6) << "lane " << k;
  }
}

TEST(LaneKernels, SpheresOverlapExactlyWhereTheirDistanceIsBelowTheReach) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> reach_of(0.01, 0.5);
  int overlapping = 0, apart = 0;
  for (int round = 0; round < 2000; ++round) {
    const LaneXyz a = random_points(rng, 0.5), b = random_points(rng, 0.5);
    const float reach = float(reach_of(rng));
    const std::uint32_t mask = bits(kernels::overlaps(a, b, reach));
    for (int k = 0; k < N; ++k) {
      const double d = (lane(a, k) - lane(b, k)).norm();
      if (std::abs(d - reach) < 1e-5) continue;  // float rounding decides there
      EXPECT_EQ(bool(mask >> k & 1u), d < reach) << d << " vs " << reach;
      (d < reach ? overlapping : apart)++;
    }
  }
  EXPECT_GT(overlapping, 1000);
  EXPECT_GT(apart, 1000);
}

TEST(LaneKernels, WithinIsEveryCoordinateInsideTheLimit) {
  std::mt19937_64 rng(7);
  for (int round = 0; round < 500; ++round) {
    LaneXyz p = random_points(rng, 2.0);
    if (round % 10 == 0) p.y[round % N] = std::numeric_limits<float>::quiet_NaN();
    const std::uint32_t mask = bits(kernels::within(p, 1.5f));
    for (int k = 0; k < N; ++k) {
      const bool inside =
          std::abs(p.x[k]) <= 1.5f && std::abs(p.y[k]) <= 1.5f && std::abs(p.z[k]) <= 1.5f;  // false for NaN
      EXPECT_EQ(bool(mask >> k & 1u), inside);
    }
  }
}

// A lane clear of the field is clear by the scalar node bound and inside the grid; a point well
// inside the grid whose scalar bound has room to spare is found clear.
TEST(LaneKernels, ClearOfFieldAgreesWithTheScalarNodeBounds) {
  Scene scene;
  scene.objects.push_back({"box", {test::box_shape(Eigen::Vector3d(0.4, 0.3, 0.2), Eigen::Vector3d(0.2, 0.1, 0.3))}});
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.6, -0.6, -0.4), Eigen::Vector3d(0.8, 0.7, 0.9));
  const auto sdf = test::analytic_sdf(scene, box, 0.02, 0.3);
  const NodeBoundGrid fine(*sdf, 1), coarse(*sdf, 4);
  const Eigen::Vector3d lo = sdf->origin(), hi = sdf->point(sdf->dims()[0] - 1, sdf->dims()[1] - 1, sdf->dims()[2] - 1);
  const float margin = 1e-4f;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> need_of(0.0, 0.25);
  int clear = 0, found = 0;
  for (int round = 0; round < 3000; ++round) {
    const LaneXyz p = random_points(rng, 0.9);
    const float need = float(need_of(rng)) + margin;
    const std::uint32_t mask =
        kernels::clear_of_field(p, need, margin, (1u << N) - 1, lo, hi, round % 2 ? &coarse : nullptr, fine, false);
    for (int k = 0; k < N; ++k) {
      const Eigen::Vector3d q = lane(p, k);
      const double bound = std::max(coarse.lower_bound(q), fine.lower_bound(q));
      const bool inside = (q.array() >= lo.array() + margin).all() && (q.array() <= hi.array() - margin).all();
      if (mask >> k & 1u) {
        ++clear;
        EXPECT_TRUE(inside) << q.transpose();
        EXPECT_GE(bound, need - 1e-4) << q.transpose();
      } else if (inside && fine.lower_bound(q) >= need + 1e-4) {
        ADD_FAILURE() << "clear by the fine bound but not found: " << q.transpose();
      }
      found += inside && fine.lower_bound(q) >= need + 1e-4;
    }
  }
  EXPECT_GT(clear, 1000);
  EXPECT_GT(found, 1000);
}

// A shape's exact answer at a point: its squared distance from the outside and its depth inside
// (> 0 inside: the distance to the nearest face).
struct ExactGap {
  double out2, depth;
};

// 2000 random shapes (`draw(rng)` gives the kernel's gaps at lanes of points and the exact answer
// at a point), 8 random points each: every lane within float rounding of the exact answer.
template <class Draw>
void expect_exact_gaps(std::uint64_t seed, Draw draw) {
  std::mt19937_64 rng(seed);
  int inside = 0, outside = 0;
  for (int round = 0; round < 2000; ++round) {
    const auto [kernel, exact] = draw(rng);
    const LaneXyz p = random_points(rng, 0.5);
    const kernels::LaneGap g = kernel(lanes::load(p.x), lanes::load(p.y), lanes::load(p.z));
    for (int k = 0; k < N; ++k) {
      const Eigen::Vector3d q = lane(p, k);
      const ExactGap e = exact(q);
      EXPECT_NEAR(g.out2[k], e.out2, 1e-6) << q.transpose();
      EXPECT_NEAR(g.inside[k], e.depth > 0 ? -e.depth : 0.0, 1e-6) << q.transpose();
      (e.depth > 0 ? inside : outside)++;
    }
  }
  EXPECT_GT(inside, 500);
  EXPECT_GT(outside, 5000);
}

// Outside: the squared distance to the box (Eigen's exterior distance); inside: the distance to
// the nearest face.
TEST(LaneKernels, BoxGapIsTheExactDistanceToTheBox) {
  expect_exact_gaps(13, [](std::mt19937_64& rng) {
    std::uniform_real_distribution<double> size(0.01, 0.4);
    const std::array<float, 3> half{float(size(rng)), float(size(rng)), float(size(rng))};
    const Eigen::Vector3d h(half[0], half[1], half[2]);
    return std::pair{
        [half](lanes::F x, lanes::F y, lanes::F z) { return kernels::box_gap(x, y, z, half.data()); },
        [h](const Eigen::Vector3d& q) {
          return ExactGap{Eigen::AlignedBox3d(-h, h).squaredExteriorDistance(q), (h - q.cwiseAbs()).minCoeff()};
        }};
  });
}

// The cylinder in (radius, height) coordinates is a rectangle: the same distances in 2-D.
TEST(LaneKernels, CylinderGapIsTheExactDistanceToTheCylinder) {
  expect_exact_gaps(17, [](std::mt19937_64& rng) {
    std::uniform_real_distribution<double> size(0.01, 0.4);
    const float radius = float(size(rng)), half_length = float(size(rng));
    return std::pair{
        [=](lanes::F x, lanes::F y, lanes::F z) { return kernels::cylinder_gap(x, y, z, radius, half_length); },
        [=](const Eigen::Vector3d& q) {
          const Eigen::AlignedBox2d section(Eigen::Vector2d(-radius, -half_length),
                                            Eigen::Vector2d(radius, half_length));
          const Eigen::Vector2d rz(std::hypot(q.x(), q.y()), q.z());
          return ExactGap{section.squaredExteriorDistance(rz),
                          std::min(double(radius) - rz.x(), double(half_length) - std::abs(rz.y()))};
        }};
  });
}

// The lanes' table reads agree with the scalar lookup (formats::SelfDistanceTable::lower_bound on
// the same values) in every lane: 1-D and 2-D tables, joints in any slot, points off the grid and
// NaN.
TEST(LaneKernels, TableApartAgreesWithTheScalarLookup) {
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int apart = 0, near = 0;
  for (int round = 0; round < 400; ++round) {
    formats::SelfDistanceTable t;
    const bool two = round % 2 == 0;
    t.lower = {-2.0 + unit(rng), -1.5 + unit(rng)};
    t.step = {0.02 + 0.1 * unit(rng), 0.02 + 0.1 * unit(rng)};
    t.slope = {0.3 * unit(rng), 0.3 * unit(rng)};
    t.count = {2 + int(40 * unit(rng)), two ? 2 + int(40 * unit(rng)) : 1};
    std::vector<std::uint16_t> tenths(std::size_t(t.count[0] * t.count[1]));
    for (auto& v : tenths) v = std::uint16_t(2000 * unit(rng));  // up to 0.2 m
    t.distance.clear();
    for (auto v : tenths) t.distance.push_back(float(1e-4 * v));
    const int slot[2] = {int(round % 3), two ? int(3 + round % 2) : -1};
    const double inv_step[2] = {1 / t.step[0], 1 / t.step[1]};
    std::array<std::array<double, 5>, N> qs;
    const double* q[N];
    for (int k = 0; k < N; ++k) {
      for (double& v : qs[std::size_t(k)]) v = -3 + 6 * unit(rng);  // beyond the grid too
      if (round % 17 == 0 && k == 3)
        qs[std::size_t(k)][std::size_t(slot[0])] = std::numeric_limits<double>::quiet_NaN();
      q[k] = qs[std::size_t(k)].data();
    }
    const double padding = 0.1 * unit(rng);
    const std::uint32_t mask =
        kernels::table_apart({slot, t.lower, t.step, inv_step, t.slope, t.count, tenths.data()}, q, padding, false);
    for (int k = 0; k < N; ++k) {
      const double x0 = q[k][slot[0]], x1 = slot[1] >= 0 ? q[k][slot[1]] : 0.0;
      // The scalar lookup on the float distances: the same node and loss; values within rounding.
      const double bound = t.lower_bound(x0, x1);
      if (std::abs(bound - padding) < 1e-6) continue;
      EXPECT_EQ(bool(mask >> k & 1u), bound > padding)
          << "round " << round << " lane " << k << ": " << bound << " vs " << padding;
      (bound > padding ? apart : near)++;
    }
  }
  EXPECT_GT(apart, 300);
  EXPECT_GT(near, 300);
}
