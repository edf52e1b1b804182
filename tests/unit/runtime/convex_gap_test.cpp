// convex_gap against FCL's own distances: a lower bound always, and a tight one.
#include <gtest/gtest.h>

#include <fcl/fcl.h>

#include <array>
#include <map>
#include <random>

#include "dmgplace/runtime/geometry/convex_gap.hpp"

using namespace dmgplace;

namespace {
Eigen::Isometry3d random_pose(std::mt19937_64& rng, double spread) {
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(-spread, spread);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
  t.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return t;
}

struct Solid {
  runtime::ConvexSolid convex;
  std::shared_ptr<fcl::CollisionGeometryd> fcl;
};

Solid random_solid(std::mt19937_64& rng, int kind) {
  std::uniform_real_distribution<double> s(0.02, 0.3);
  const double a = s(rng), b = s(rng), c = s(rng);
  switch (kind) {
    case 0:
      return {runtime::ConvexSolid::box(Eigen::Vector3d(a, b, c) / 2), std::make_shared<fcl::Boxd>(a, b, c)};
    case 1:
      return {runtime::ConvexSolid::cylinder(a, b / 2), std::make_shared<fcl::Cylinderd>(a, b)};
    default:
      return {runtime::ConvexSolid::sphere(a), std::make_shared<fcl::Sphered>(a)};
  }
}
// A box's closed surface with a grid of k x k squares on every face (inner face and edge vertices
// are not extreme: a climb can stop on one when a face lies across the direction).
struct GridBox {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3i> triangles;
};
GridBox grid_box(int k, const Eigen::Vector3d& half) {
  GridBox out;
  std::map<std::array<int, 3>, int> index;
  auto vertex = [&](std::array<int, 3> g) {
    auto [it, fresh] = index.emplace(g, int(out.points.size()));
    if (fresh)
      out.points.emplace_back(half.x() * (2.0 * g[0] / k - 1), half.y() * (2.0 * g[1] / k - 1),
                              half.z() * (2.0 * g[2] / k - 1));
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {0, k}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          auto at = [&](int a, int b) {
            std::array<int, 3> g{};
            g[std::size_t(axis)] = side;
            g[std::size_t(u)] = a;
            g[std::size_t(v)] = b;
            return vertex(g);
          };
          out.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
          out.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
  return out;
}
}  // namespace

TEST(ConvexGap, NeverAboveFclsDistanceAndCloseToItWhenApart) {
  std::mt19937_64 rng(7);
  int apart = 0, touching = 0;
  for (int n = 0; n < 6000; ++n) {
    const Solid a = random_solid(rng, n % 3), b = random_solid(rng, (n / 3) % 3);
    const Eigen::Isometry3d ta = random_pose(rng, 0.4), tb = random_pose(rng, 0.4);
    fcl::CollisionObjectd oa(a.fcl, ta.linear(), ta.translation()), ob(b.fcl, tb.linear(), tb.translation());
    fcl::CollisionRequestd creq;
    fcl::CollisionResultd cres;
    const double gap = runtime::convex_gap(a.convex, ta, b.convex, tb, 1e-7);
    if (fcl::collide(&oa, &ob, creq, cres) > 0) {
      ASSERT_LE(gap, 1e-9) << "case " << n << ": a gap between touching solids";
      ++touching;
      continue;
    }
    fcl::DistanceRequestd dreq;
    dreq.gjk_solver_type = fcl::GST_INDEP;
    dreq.distance_tolerance = 1e-8;
    fcl::DistanceResultd dres;
    fcl::distance(&oa, &ob, dreq, dres);
    ASSERT_LE(gap, dres.min_distance + 1e-6) << "case " << n;
    if (dres.min_distance > 1e-3) {
      EXPECT_GT(gap, dres.min_distance - 1e-4)
          << "case " << n << " kinds " << n % 3 << (n / 3) % 3 << ": a loose bound";
      ++apart;
    }
  }
  EXPECT_GT(apart, 1000);
  EXPECT_GT(touching, 500);
}

// A caller asking only whether the gap exceeds a threshold (`enough`) stops early: its answer
// must be the full computation's on which side of the threshold the gap lies, and still a bound.
TEST(ConvexGap, AThresholdQueryAgreesWithTheFullGapOnItsSide) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> threshold(-0.01, 0.2);
  int above = 0, below = 0;
  for (int n = 0; n < 6000; ++n) {
    const Solid a = random_solid(rng, n % 3), b = random_solid(rng, (n / 3) % 3);
    const Eigen::Isometry3d ta = random_pose(rng, 0.4), tb = random_pose(rng, 0.4);
    const double enough = threshold(rng);
    const double full = runtime::convex_gap(a.convex, ta, b.convex, tb);
    const double quick = runtime::convex_gap(a.convex, ta, b.convex, tb, 1e-5, enough);
    ASSERT_LE(quick, full + 1e-5) << "case " << n << ": the early answer is not a lower bound";
    // Within GJK's tolerance of the threshold the two may stop on either side of it.
    if (std::abs(full - enough) <= 2e-5) continue;
    ASSERT_EQ(quick > enough, full > enough)
        << "case " << n << ": full " << full << ", quick " << quick << ", threshold " << enough;
    // Below a positive threshold the answer is refined as the full one is (certificates use it as
    // their clearance); a sign query (threshold <= 0) may stop with any bound on its side.
    if (full < enough && enough > 0) {
      ASSERT_NEAR(quick, full, 1e-5) << "case " << n << ", threshold " << enough;
    }
    ++(full > enough ? above : below);
  }
  EXPECT_GT(above, 1000);
  EXPECT_GT(below, 1000);
}

// A box given by its eight corners is the same solid as the box: the hull path and the primitive
// path agree, and a hull's support is its farthest vertex.
TEST(ConvexGap, HullOfABoxsCornersMeasuresAsTheBox) {
  std::mt19937_64 rng(11);
  const Eigen::Vector3d half(0.1, 0.05, 0.2);
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i)
    corners.emplace_back(i & 1 ? half.x() : -half.x(), i & 2 ? half.y() : -half.y(), i & 4 ? half.z() : -half.z());
  corners.push_back(Eigen::Vector3d::Zero());  // an inner point changes nothing
  const auto hull = runtime::ConvexSolid::hull(corners), box = runtime::ConvexSolid::box(half);
  const auto other = runtime::ConvexSolid::cylinder(0.05, 0.1);
  for (int n = 0; n < 2000; ++n) {
    const Eigen::Isometry3d ta = random_pose(rng, 0.5), tb = random_pose(rng, 0.5);
    EXPECT_NEAR(runtime::convex_gap(hull, ta, other, tb, 1e-8), runtime::convex_gap(box, ta, other, tb, 1e-8), 1e-5)
        << n;
    const Eigen::Vector3d d = random_pose(rng, 1).translation();
    EXPECT_NEAR(hull.support(d).dot(d), box.support(d).dot(d), 1e-12);
  }
}

// A hull given as its triangulated surface climbs to its supports. A box's surface with a grid of
// vertices on every face (inner face and edge vertices are not extreme: a climb can stop on one
// when a face lies across the direction) must still answer the farthest vertex exactly, from any
// start: along random directions, along the faces' normals and along edge and corner diagonals
// (the flat cases), with starts anywhere on the surface.
TEST(ConvexGap, ClimbedHullSupportsAreTheFarthestVertexFromAnyStart) {
  const int k = 4;  // grid steps per face side
  const Eigen::Vector3d half(0.1, 0.05, 0.2);
  const auto [points, triangles] = grid_box(k, half);
  const auto climbed = runtime::ConvexSolid::hull(points, triangles);
  std::vector<Eigen::Vector3d> directions;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x || y || z) directions.emplace_back(x, y, z);
  std::mt19937_64 rng(12);
  for (int n = 0; n < 2000; ++n) directions.push_back(random_pose(rng, 1).translation());
  std::uniform_int_distribution<int> any(0, int(points.size()) - 1);
  for (const auto& d : directions) {
    double farthest = -1e300;
    for (const auto& p : points) farthest = std::max(farthest, p.dot(d));
    for (int trial = 0; trial < 8; ++trial) {
      int start = trial == 0 ? -1 : any(rng);
      EXPECT_EQ(climbed.support(d, start).dot(d), farthest) << d.transpose() << " from " << start;
      ASSERT_GE(start, 0);
      EXPECT_EQ(points[std::size_t(start)].dot(d), farthest) << "the start is left at the answer";
    }
  }
}

// Along a motion each query starts where the last one of the same two solids ended (GapHint). A
// start is only a direction: hinted answers are the fresh ones' (a lower bound, on the same side of
// a threshold, as tight), whether the hint is the last query's or garbage (any direction and
// length, vertex indices out of range).
TEST(ConvexGap, AHintedStartGivesTheFreshAnswers) {
  std::mt19937_64 rng(13);
  const auto [points, triangles] = grid_box(4, Eigen::Vector3d(0.1, 0.05, 0.2));
  const auto climbed = runtime::ConvexSolid::hull(points, triangles);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> threshold(-0.01, 0.2), scale(-6, 1);
  std::uniform_int_distribution<int> vertex(-3, int(points.size()) + 3);
  int compared = 0, stale = 0, apart = 0;
  for (int n = 0; n < 400; ++n) {
    const Solid other = random_solid(rng, n % 3);
    const bool hull = n % 2 == 0;
    const runtime::ConvexSolid& a = hull ? climbed : other.convex;
    const Solid b = random_solid(rng, (n / 2) % 3);
    Eigen::Isometry3d ta = random_pose(rng, 0.4);
    const Eigen::Isometry3d tb = random_pose(rng, 0.4);
    runtime::GapHint hint;
    for (int step = 0; step < 30; ++step) {
      // A small move (5 mm, 0.05 rad), as between states along a motion.
      ta.translation() += 0.005 * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
      ta.linear() =
          (Eigen::AngleAxisd(0.05, Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized()) * ta.linear()).eval();
      if (step % 7 == 6) {  // garbage: any direction, any length, any vertices
        hint.v = std::pow(10.0, scale(rng)) * Eigen::Vector3d(g(rng), g(rng), g(rng));
        hint.from_a = vertex(rng);
        hint.from_b = vertex(rng);
        ++stale;
      }
      const double enough = step % 3 == 0 ? std::numeric_limits<double>::infinity() : threshold(rng);
      const double full = runtime::convex_gap(a, ta, b.convex, tb);
      const double hinted = runtime::convex_gap(a, ta, b.convex, tb, 1e-5, enough, &hint);
      // Overlapping solids (full <= 0) have no gap to prove: any bound <= 0 is an answer.
      ASSERT_LE(hinted, std::max(full, 0.0) + 1e-5) << "case " << n << " step " << step << ": not a lower bound";
      if (std::isinf(enough)) {
        if (full > 1e-5) {
          ASSERT_NEAR(hinted, full, 2e-5) << "case " << n << " step " << step << ": a loose bound";
        }
      } else if (std::abs(full - enough) > 2e-5) {
        ASSERT_EQ(hinted > enough, full > enough) << "case " << n << " step " << step << ": full " << full
                                                  << ", hinted " << hinted << ", threshold " << enough;
        if (full < enough && full > 1e-5) {
          ASSERT_NEAR(hinted, full, 2e-5) << "case " << n << " step " << step;
        }
      }
      apart += full > 1e-5;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 12000);
  EXPECT_GT(apart, 4000);
  EXPECT_GT(stale, 1500);
}

// The direction a gap was proven along separates the solids by that gap: a's farthest point
// against it and b's farthest point along it (the exact supports) lie at least the gap apart
// along it. Directional certificates rest on that plane.
TEST(ConvexGap, TheSeparationProvesTheGapAlongIt) {
  std::mt19937_64 rng(21);
  int apart = 0;
  for (int n = 0; n < 6000; ++n) {
    const Solid a = random_solid(rng, n % 3), b = random_solid(rng, (n / 3) % 3);
    const Eigen::Isometry3d ta = random_pose(rng, 0.4), tb = random_pose(rng, 0.4);
    Eigen::Vector3d along;
    const double gap =
        runtime::convex_gap(a.convex, ta, b.convex, tb, 1e-7, std::numeric_limits<double>::infinity(), nullptr, &along);
    if (!(gap > 0)) continue;
    ++apart;
    ASSERT_NEAR(along.norm(), 1.0, 1e-9) << "case " << n;
    const Eigen::Vector3d a_near = ta * a.convex.support(ta.linear().transpose() * -along);
    const Eigen::Vector3d b_near = tb * b.convex.support(tb.linear().transpose() * along);
    ASSERT_GE(along.dot(a_near - b_near), gap - 1e-9) << "case " << n;
  }
  EXPECT_GT(apart, 1000);
}
