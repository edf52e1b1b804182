#include "dmgplace/runtime/collision/displacement_bound.hpp"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>

#include "dmgplace/runtime/robot/kinematics.hpp"
#include "fixtures.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {
// The built-in arm, and for a link: the chain joints from a frame above it down to it.
struct Arm {
  RobotModel model = test::read_robot_model(test::source_dir() / "datasets/robots/dmgarm/dmgarm.urdf");
  Kinematics kin{model, "dmgarm_link0", "dmgarm_tcp"};

  int parent_joint(int link) const {
    for (std::size_t j = 0; j < model.joints.size(); ++j)
      if (model.joints[j].child == link) return int(j);
    return -1;
  }
  // Chain joints between `frame` (an ancestor of `link`) and `link`, top first.
  std::vector<int> joints_between(int frame, int link) const {
    std::vector<int> out;
    for (int l = link; l != frame;) {
      const int j = parent_joint(l);
      if (j < 0) break;
      if (kin.chain_slot(j) >= 0) out.push_back(j);
      l = model.joints[std::size_t(j)].parent;
    }
    std::reverse(out.begin(), out.end());
    return out;
  }
  std::vector<int> moving_links() const {
    const auto moving = kin.moving_links();
    std::vector<int> out;
    for (std::size_t l = 0; l < moving.size(); ++l)
      if (moving[l]) out.push_back(int(l));
    return out;
  }
  std::vector<int> ancestors(int link) const {  // nearest first, up to the root
    std::vector<int> out;
    for (int j = parent_joint(link); j >= 0; j = parent_joint(model.joints[std::size_t(j)].parent))
      out.push_back(model.joints[std::size_t(j)].parent);
    return out;
  }
  // The motion of a ball on `link` as the checker builds it: axes and origins at q, in world
  // coordinates (any frame the joints do not move measures the same distances).
  BallMotion motion(const std::vector<Eigen::Isometry3d>& poses, int frame, int link, const Eigen::Vector3d& center,
                    double radius, const Eigen::VectorXd& u) const {
    BallMotion m(poses[std::size_t(link)] * center, radius);
    for (int j : joints_between(frame, link)) {
      const Joint& jt = model.joints[std::size_t(j)];
      const Eigen::Isometry3d& T = poses[std::size_t(jt.child)];
      if (jt.type == JointType::Prismatic)
        m.add_prismatic(T.linear() * jt.axis.normalized(), u[kin.chain_slot(j)], 1e6);
      else m.add_revolute(T.linear() * jt.axis.normalized(), T.translation(), u[kin.chain_slot(j)], 1e6);
    }
    return m;
  }
  DisplacementBound bound(const std::vector<Eigen::Isometry3d>& poses, int frame, int link,
                          const Eigen::Vector3d& center, double radius, const Eigen::VectorXd& u) const {
    return motion(poses, frame, link, center, radius, u).bound();
  }
};

Eigen::VectorXd random_unit(int n, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0, 1);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = g(rng);
  return v.normalized();
}

// Where a point of `link` (link frame) is at q, in `frame`'s coordinates.
Eigen::Vector3d in_frame(const Arm& arm, const Eigen::VectorXd& q, int frame, int link, const Eigen::Vector3d& p) {
  std::vector<Eigen::Isometry3d> poses;
  arm.kin.link_poses(q, poses);
  return poses[std::size_t(frame)].inverse() * (poses[std::size_t(link)] * p);
}
}  // namespace

// Every point of the ball, measured in a frame above it (the base or a link between), moves no
// farther than the bound says, at every t up to a full radian, and no farther than the clearance
// before time_to_move(clearance). Near t = 0 the bound is close to the true motion: loosening any
// of its terms shows as a lower ratio.
TEST(DisplacementBound, BoundsEveryPointOfTheBallAlongTheMotion) {
  Arm arm;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  const std::vector<int> links = arm.moving_links();
  ASSERT_GE(links.size(), 6u);
  std::vector<double> tightness;
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    Eigen::VectorXd q(arm.kin.dof());
    for (int i = 0; i < arm.kin.dof(); ++i)
      q[i] = arm.kin.lower()[i] + unit(rng) * (arm.kin.upper()[i] - arm.kin.lower()[i]);
    Eigen::VectorXd u = random_unit(arm.kin.dof(), rng);
    const int link = links[std::size_t(rng() % links.size())];
    const auto above = arm.ancestors(link);
    const int frame = trial % 2 == 0 ? arm.kin.base_link() : above[std::size_t(rng() % above.size())];
    const Eigen::Vector3d center = 0.1 * random_unit(3, rng) * unit(rng);
    double radius = 0.05 * unit(rng);
    if (trial % 4 >= 2 && arm.joints_between(frame, link).size() > 3) {
      // A motion that leaves the center still at first (u in the null space of its Jacobian), on a
      // point ball: only the second-order terms bound it, so none of them can be dropped.
      Eigen::MatrixXd J(3, arm.kin.dof());
      for (int i = 0; i < arm.kin.dof(); ++i) {
        Eigen::VectorXd dq = Eigen::VectorXd::Zero(arm.kin.dof());
        dq[i] = 1e-6;
        J.col(i) = (in_frame(arm, q + dq, frame, link, center) - in_frame(arm, q - dq, frame, link, center)) / 2e-6;
      }
      u = Eigen::JacobiSVD<Eigen::MatrixXd>(J, Eigen::ComputeFullV).matrixV().col(arm.kin.dof() - 1).normalized();
      radius = 0;
    }
    std::vector<Eigen::Isometry3d> poses;
    arm.kin.link_poses(q, poses);
    const DisplacementBound b = arm.bound(poses, frame, link, center, radius, u);
    std::vector<Eigen::Vector3d> points{center};
    for (int k = 0; k < 12 && radius > 0; ++k) points.push_back(center + radius * random_unit(3, rng));
    std::vector<Eigen::Vector3d> start;
    for (const auto& p : points) start.push_back(in_frame(arm, q, frame, link, p));
    auto moved = [&](double t) {
      double d = 0;
      for (std::size_t k = 0; k < points.size(); ++k)
        d = std::max(d, (in_frame(arm, q + t * u, frame, link, points[k]) - start[k]).norm());
      return d;
    };
    for (double t = 1e-3; t <= 1.0; t *= 1.25) {
      const double d = moved(t);
      ASSERT_LE(d, b.displacement(t) + 1e-12) << "t = " << t << " link " << link << " frame " << frame;
      if (t < 1.1e-3 && radius > 0 && d > 1e-6) tightness.push_back(d / b.displacement(t));
    }
    for (const double clearance : {0.002, 0.01, 0.05}) {
      const double T = b.time_to_move(clearance);
      ASSERT_GT(T, 0.0);
      for (double t = T / 16; t <= std::min(T, 2.0); t += T / 16)
        ASSERT_LT(moved(t), clearance) << "t = " << t << " of " << T;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 1200);
  ASSERT_GT(tightness.size(), 100u);
  std::sort(tightness.begin(), tightness.end());
  const double median = tightness[tightness.size() / 2];
  RecordProperty("median_tightness", std::to_string(median));
  EXPECT_GT(median, 0.6) << "the bound is far above the true motion at small t";
}

// Along a direction n: no point of the ball advances along n (either sense) farther than the
// bound with the first-order term along n (BallVelocity::along), at every t up to a radian; n
// mostly near-perpendicular to the center's velocity, where that term is small and the drift terms
// carry the bound.
TEST(DisplacementBound, BoundsEveryPointOfTheBallAlongADirection) {
  Arm arm;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> unit(0, 1);
  const std::vector<int> links = arm.moving_links();
  const int base = arm.kin.base_link();
  std::vector<double> tightness;
  double worst = 0;
  for (int trial = 0; trial < 600; ++trial) {
    Eigen::VectorXd q(arm.kin.dof());
    for (int i = 0; i < arm.kin.dof(); ++i)
      q[i] = arm.kin.lower()[i] + unit(rng) * (arm.kin.upper()[i] - arm.kin.lower()[i]);
    const Eigen::VectorXd u = random_unit(arm.kin.dof(), rng);
    const int link = links[std::size_t(rng() % links.size())];
    const Eigen::Vector3d center = 0.1 * random_unit(3, rng) * unit(rng);
    const double radius = trial % 3 == 0 ? 0.0 : 0.05 * unit(rng);
    std::vector<Eigen::Isometry3d> poses;
    arm.kin.link_poses(q, poses);
    const BallMotion m = arm.motion(poses, base, link, center, radius, u);
    const DisplacementBound b = m.bound();
    const BallVelocity v = m.velocity();
    // Perpendicular to the center's velocity, tilted a little at random.
    Eigen::Vector3d n = random_unit(3, rng);
    if (v.linear.norm() > 1e-9 && trial % 4 != 0)
      n = (n - n.dot(v.linear.normalized()) * v.linear.normalized() + 0.05 * unit(rng) * random_unit(3, rng))
              .normalized();
    const DisplacementBound along = b.along(v.along(n));
    std::vector<Eigen::Vector3d> points{center};
    for (int k = 0; k < 24 && radius > 0; ++k) points.push_back(center + radius * random_unit(3, rng));
    std::vector<Eigen::Vector3d> start;
    for (const auto& p : points) start.push_back(in_frame(arm, q, base, link, p));
    for (double t = 1e-3; t <= 1.0; t *= 1.25)
      for (const double sense : {1.0, -1.0}) {
        double d = 0;
        for (std::size_t k = 0; k < points.size(); ++k)
          d = std::max(d, n.dot(in_frame(arm, q + sense * t * u, base, link, points[k]) - start[k]));
        ASSERT_LE(d, along.displacement(t) + 1e-12) << "t = " << t << " link " << link << " trial " << trial;
        if (d > 1e-6) worst = std::max(worst, d / along.displacement(t));
      }
  }
  RecordProperty("largest_ratio", std::to_string(worst));
  EXPECT_GT(worst, 0.5) << "the directional bound is far above every motion";
}

// Two balls: the sum of their displacements stays under the summed bound (a link pair's).
TEST(DisplacementBound, SumOfTwoBallsIsBoundedByTheirSum) {
  Arm arm;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(0, 1);
  const int base = arm.kin.base_link(), tip = arm.kin.tip_link();
  const auto above = arm.ancestors(tip);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::VectorXd q(arm.kin.dof());
    for (int i = 0; i < arm.kin.dof(); ++i)
      q[i] = arm.kin.lower()[i] + unit(rng) * (arm.kin.upper()[i] - arm.kin.lower()[i]);
    const Eigen::VectorXd u = random_unit(arm.kin.dof(), rng);
    const int a = tip, b = above[std::size_t(rng() % (above.size() - 1))];
    std::vector<Eigen::Isometry3d> poses;
    arm.kin.link_poses(q, poses);
    const Eigen::Vector3d ca = 0.05 * random_unit(3, rng), cb = 0.05 * random_unit(3, rng);
    DisplacementBound sum = arm.bound(poses, base, a, ca, 0.02, u);
    sum.add(arm.bound(poses, base, b, cb, 0.02, u));
    for (double t = 1e-3; t <= 1.0; t *= 1.5) {
      const double d = (in_frame(arm, q + t * u, base, a, ca) - in_frame(arm, q, base, a, ca)).norm() +
                       (in_frame(arm, q + t * u, base, b, cb) - in_frame(arm, q, base, b, cb)).norm();
      ASSERT_LE(d, sum.displacement(t) + 1e-12) << "t = " << t;
    }
    EXPECT_LE(sum.time_to_move(0.01), std::min(arm.bound(poses, base, a, ca, 0.02, u).time_to_move(0.01),
                                               arm.bound(poses, base, b, cb, 0.02, u).time_to_move(0.01)) +
                                          1e-12);
  }
}

// A caller that needs only `enough` may get any guaranteed time past it: never more than the full
// answer, and either the full answer or at least `enough`. Over random arm bounds, clearances and
// needs, both cheap exits (the static and the log-free Gronwall bound) and the full Taylor root
// must be taken.
TEST(DisplacementBound, TimeToMoveGivenEnoughIsTheFullAnswerOrPastEnough) {
  Arm arm;
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(0, 1);
  const int base = arm.kin.base_link(), tip = arm.kin.tip_link();
  int early = 0, full = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::VectorXd q(arm.kin.dof());
    for (int i = 0; i < arm.kin.dof(); ++i)
      q[i] = arm.kin.lower()[i] + unit(rng) * (arm.kin.upper()[i] - arm.kin.lower()[i]);
    std::vector<Eigen::Isometry3d> poses;
    arm.kin.link_poses(q, poses);
    const DisplacementBound b =
        arm.bound(poses, base, tip, 0.05 * random_unit(3, rng), 0.05 * unit(rng), random_unit(arm.kin.dof(), rng));
    const double clearance = 0.001 + 0.2 * unit(rng), all = b.time_to_move(clearance);
    const double enough = all * (0.2 + 1.6 * unit(rng));
    const double t = b.time_to_move(clearance, enough);
    ASSERT_LE(t, all + 1e-15) << "a cheaper answer cannot prove more";
    if (t == all) ++full;
    else ASSERT_GE(t, enough) << "short of the full answer and of what was needed";
    if (t < all) ++early;
  }
  EXPECT_GT(early, 100);
  EXPECT_GT(full, 100);
}

// Gronwall's time takes log1p(x) / x from its Pade form: it must never exceed it (a longer
// certificate than the bound proves), and where the logarithm is skipped (x <= 0.5) it must be
// within 2e-4 of it. Dense in x from 1e-9 to 1e4.
TEST(DisplacementBound, PadeLogarithmStaysBelowLog1pAndCloseBelowHalf) {
  int checked = 0;
  for (double x = 1e-9; x < 1e4; x *= 1.0001, ++checked) {
    const double exact = std::log1p(x) / x, pade = log1p_ratio_lower(x);
    ASSERT_LE(pade, exact) << "x = " << x;
    if (x <= 0.5) {
      ASSERT_GE(pade, exact * (1 - 2e-4)) << "x = " << x;
    }
  }
  EXPECT_GT(checked, 100000);
}

// A ball that no joint moves never runs out of clearance; one on the axis of the only moving joint
// turns in place (first order 0 at the center) and moves only through its radius.
TEST(DisplacementBound, EdgeCases) {
  BallMotion still(Eigen::Vector3d(1, 0, 0), 0.1);
  EXPECT_TRUE(std::isinf(still.bound().time_to_move(0.01)));
  BallMotion on_axis(Eigen::Vector3d(0, 0, 0.5), 0.0);
  on_axis.add_revolute(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), 1.0, 0.5);
  EXPECT_DOUBLE_EQ(on_axis.bound().first_order, 0.0);
  EXPECT_EQ(on_axis.bound().displacement(0.3), 0.0);
  BallMotion slide(Eigen::Vector3d(0, 0, 0), 0.05);
  slide.add_prismatic(Eigen::Vector3d::UnitX(), -0.5, 1.0);
  EXPECT_NEAR(slide.bound().time_to_move(0.01), 0.02, 1e-12);  // 0.5 m per unit: 1 cm in 0.02
}
