#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/geometry/fast_sincos.hpp"
#include "dmgplace/runtime/robot/ik.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/runtime/robot/kinematics_lanes.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"
#include "fixtures.hpp"
#include "lane_rounds.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {
// Planar 2R arm in the x-y plane: link lengths 0.5 and 0.3, plus a fixed tool offset 0.1.
RobotModel planar_arm() {
  RobotModel m;
  m.name = "planar";
  for (auto n : {"base", "l1", "l2", "tool"}) m.links.push_back({n, {}});
  Joint j1;
  j1.name = "j1";
  j1.type = JointType::Revolute;
  j1.parent = 0;
  j1.child = 1;
  j1.lower = -3;
  j1.upper = 3;
  Joint j2 = j1;
  j2.name = "j2";
  j2.parent = 1;
  j2.child = 2;
  j2.origin.translation() = Eigen::Vector3d(0.5, 0, 0);
  Joint j3;
  j3.name = "tool";
  j3.type = JointType::Fixed;
  j3.parent = 2;
  j3.child = 3;
  j3.origin.translation() = Eigen::Vector3d(0.4, 0, 0);
  m.joints = {j1, j2, j3};
  return m;
}

RobotModel load(const std::filesystem::path& urdf, const std::filesystem::path& pkg = {}) {
  std::vector<std::filesystem::path> packages;
  if (!pkg.empty()) packages.push_back(pkg);
  return test::read_robot_model(urdf, {}, packages);
}

using test::random_q;

void expect_jacobian_matches_finite_differences(const Kinematics& k, int samples) {
  std::mt19937_64 rng(11);
  Jacobian J;
  for (int s = 0; s < samples; ++s) {
    Eigen::VectorXd q = random_q(k, rng);
    k.jacobian(q, J);
    const Eigen::Isometry3d t0 = k.tip_pose(q);
    const double h = 1e-7;
    for (int c = 0; c < k.dof(); ++c) {
      Eigen::VectorXd qh = q;
      qh[c] += h;
      const Eigen::Isometry3d t1 = k.tip_pose(qh);
      Eigen::Vector3d v = (t1.translation() - t0.translation()) / h;
      Eigen::AngleAxisd aa(t1.linear() * t0.linear().transpose());
      Eigen::Vector3d w = aa.axis() * aa.angle() / h;
      EXPECT_LT((J.block<3, 1>(0, c) - v).norm(), 1e-5) << "column " << c;
      EXPECT_LT((J.block<3, 1>(3, c) - w).norm(), 1e-5) << "column " << c;
    }
  }
}

void expect_ik_round_trips(const Kinematics& k, int samples, double min_success) {
  IkSolver ik(k);
  std::mt19937_64 rng(21);
  int ok = 0;
  for (int s = 0; s < samples; ++s) {
    Eigen::VectorXd q = random_q(k, rng);
    Eigen::Isometry3d target = k.tip_pose(q);
    Eigen::VectorXd seed = random_q(k, rng);
    IkResult r = ik.solve(target, seed, rng);
    if (!r.success) continue;
    ++ok;
    EXPECT_TRUE(k.within_limits(r.q));
    Eigen::Isometry3d back = k.tip_pose(r.q);
    EXPECT_LT((back.translation() - target.translation()).norm(), 1.1e-4);
    EXPECT_LT(Eigen::AngleAxisd(back.linear() * target.linear().transpose()).angle(), 1.1e-3);
  }
  EXPECT_GE(double(ok) / samples, min_success);
}
}  // namespace

TEST(Kinematics, PlanarArmMatchesAnalyticForwardKinematicsAndJacobian) {
  Kinematics k(planar_arm(), "base", "tool");
  ASSERT_EQ(k.dof(), 2);
  std::mt19937_64 rng(1);
  Jacobian J;
  for (int s = 0; s < 100; ++s) {
    Eigen::VectorXd q = random_q(k, rng);
    const double a = q[0], b = q[0] + q[1];
    Eigen::Vector3d p(0.5 * std::cos(a) + 0.4 * std::cos(b), 0.5 * std::sin(a) + 0.4 * std::sin(b), 0);
    EXPECT_LT((k.tip_pose(q).translation() - p).norm(), 1e-12);
    k.jacobian(q, J);
    EXPECT_NEAR(J(0, 0), -p.y(), 1e-12);
    EXPECT_NEAR(J(1, 0), p.x(), 1e-12);
    EXPECT_NEAR(J(0, 1), -0.4 * std::sin(b), 1e-12);
    EXPECT_NEAR(J(5, 1), 1.0, 1e-12);
    std::vector<Eigen::Isometry3d> poses;
    k.link_poses(q, poses);
    EXPECT_TRUE(poses[3].isApprox(k.tip_pose(q)));
  }
}

// A chain with every joint kind the tip's pose and Jacobian handle: revolute and prismatic joints
// about tilted axes under rotated origins, a mimic joint following the first, a fixed tool.
TEST(Kinematics, MixedChainTipPoseMatchesLinkPosesAndJacobianMatchesFiniteDifferences) {
  RobotModel m;
  m.name = "mixed";
  for (auto n : {"base", "l1", "l2", "l3", "l4", "tool"}) m.links.push_back({n, {}});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  auto joint = [&](const char* name, JointType type, int parent) {
    Joint j;
    j.name = name;
    j.type = type;
    j.parent = parent;
    j.child = parent + 1;
    j.lower = -2;
    j.upper = 2;
    j.origin.linear() =
        Eigen::AngleAxisd(2 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    j.origin.translation() = 0.3 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    j.axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    return j;
  };
  Joint mimic = joint("j3", JointType::Revolute, 2);
  mimic.mimic = 0;
  mimic.mimic_multiplier = -0.7;
  mimic.mimic_offset = 0.2;
  m.joints = {joint("j1", JointType::Revolute, 0), joint("j2", JointType::Prismatic, 1), mimic,
              joint("j4", JointType::Revolute, 3), joint("tool", JointType::Fixed, 4)};
  Kinematics k(m, "base", "tool");
  ASSERT_EQ(k.dof(), 3);
  expect_jacobian_matches_finite_differences(k, 50);
  std::vector<Eigen::Isometry3d> poses;
  for (int s = 0; s < 50; ++s) {
    const Eigen::VectorXd q = random_q(k, rng);
    k.link_poses(q, poses);
    Jacobian J;
    const Eigen::Isometry3d tip = k.tip_pose_and_jacobian(q, J);
    EXPECT_TRUE(poses[5].isApprox(tip, 1e-12));
    EXPECT_TRUE(k.tip_pose(q).isApprox(tip, 1e-12));
  }
}

// Quarter-turn joints (origins turned by multiples of pi/2, written as URDFs write them, to 11
// digits; axes along +-x, +-y, +-z) take Kinematics' permuted-column form: link_poses, the tip
// pose and the lane check equal the plain product origin x AngleAxis(q, axis) of the model as read;
// the float lane check stays within Kinematics::float_pose_error of it (a prismatic joint among them).
TEST(Kinematics, QuarterTurnJointsEqualTheirPlainProduct) {
  RobotModel m;
  m.name = "quarter";
  const int nj = 9;
  for (int l = 0; l <= nj; ++l) m.links.push_back({"l" + std::to_string(l), {}});
  std::mt19937_64 rng(17);
  std::uniform_int_distribution<int> pick(0, 3), axis_pick(0, 5);
  std::uniform_real_distribution<double> u(-1, 1);
  const double quarter = 1.57079632679;  // as the Panda's URDF writes it
  for (int j = 0; j < nj; ++j) {
    Joint jt;
    jt.name = "j" + std::to_string(j);
    jt.parent = j;
    jt.child = j + 1;
    jt.type = j == 4 ? JointType::Fixed : j == 6 ? JointType::Prismatic : JointType::Revolute;
    jt.lower = -2.5;
    jt.upper = 2.5;
    jt.origin.linear() = (Eigen::AngleAxisd(pick(rng) * quarter, Eigen::Vector3d::UnitX()) *
                          Eigen::AngleAxisd(pick(rng) * quarter, Eigen::Vector3d::UnitY()) *
                          Eigen::AngleAxisd(pick(rng) * quarter, Eigen::Vector3d::UnitZ()))
                             .toRotationMatrix();
    jt.origin.translation() = 0.2 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const int a = axis_pick(rng);
    jt.axis = (a < 3 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(a % 3);
    if (j == 8) jt.axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();  // one general joint among them
    m.joints.push_back(jt);
  }
  Kinematics k(m, "l0", "l" + std::to_string(nj));
  ASSERT_EQ(k.dof(), nj - 1);
  std::vector<Eigen::Isometry3d> poses;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    force_simd_path(path);
    for (int round = 0; round < 40; ++round) {
      std::vector<Eigen::VectorXd> qs;
      const double* ptr[LinkPoseLanesD::kLanes];
      for (int lane = 0; lane < LinkPoseLanesD::kLanes; ++lane) qs.push_back(random_q(k, rng));
      for (int lane = 0; lane < LinkPoseLanesD::kLanes; ++lane) ptr[lane] = qs[std::size_t(lane)].data();
      LinkPoseLanesD in_lanes;
      k.lanes().link_poses(ptr, in_lanes);
      LinkPoseLanesF floats;  // the lane sphere check's kinematics: within its error bound
      k.lanes().link_poses(ptr, floats);
      const double reach = 1.0, bound = k.lanes().float_pose_error(reach);
      for (int lane = 0; lane < LinkPoseLanesD::kLanes; ++lane) {
        const Eigen::VectorXd& q = qs[std::size_t(lane)];
        k.link_poses(q, poses);
        Eigen::Isometry3d want = Eigen::Isometry3d::Identity();
        for (int j = 0, slot = 0; j < nj; ++j) {
          const Joint& jt = m.joints[std::size_t(j)];
          Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
          if (jt.type == JointType::Revolute)
            motion.linear() = Eigen::AngleAxisd(q[slot++], jt.axis).toRotationMatrix();
          if (jt.type == JointType::Prismatic) motion.translation() = q[slot++] * jt.axis;
          want = want * jt.origin * motion;
          const auto l = std::size_t(j + 1);
          ASSERT_LT((poses[l].matrix() - want.matrix()).cwiseAbs().maxCoeff(), 1e-8) << "link " << l;
          for (int e = 0; e < 12; ++e) {
            const double w = e < 9 ? want.linear()(e / 3, e % 3) : want.translation()[e - 9];
            ASSERT_NEAR(in_lanes.pose[l][std::size_t(e)][std::size_t(lane)], w, 1e-8)
                << to_string(path) << " link " << l << " element " << e;
          }
          for (int axis = 0; axis < 3; ++axis) {
            const auto& f = floats.pose[l];
            auto at = [&](int e) { return f[std::size_t(e)][std::size_t(lane)]; };
            const float p[3] = {axis == 0 ? float(reach) : 0.f, axis == 1 ? float(reach) : 0.f,
                                axis == 2 ? float(reach) : 0.f};
            Eigen::Vector3d got;
            for (int r = 0; r < 3; ++r)
              got[r] = double(at(3 * r) * p[0] + at(3 * r + 1) * p[1] + at(3 * r + 2) * p[2] + at(9 + r));
            ASSERT_LE((got - want * (reach * Eigen::Vector3d::Unit(axis))).norm(), bound)
                << to_string(path) << " link " << l;
          }
        }
        EXPECT_LT((k.tip_pose(q).matrix() - want.matrix()).cwiseAbs().maxCoeff(), 1e-8);
      }
    }
  }
  expect_jacobian_matches_finite_differences(k, 30);
}

// Lane check frames (Kinematics::lane_frame): every link is placed by its frame's float pose from
// frame_poses_lanes and its offset there, within float_pose_error of link_poses (for points that
// far from the frame's origin), on both paths. Frames are exactly the roots and the links a chain
// joint moves (with the base at the root; else every link); a set value changes plan_version()
// and the offsets follow it.
static void expect_frames_place_every_link(const Kinematics& k, std::uint64_t seed) {
  const auto& m = k.model();
  for (std::size_t l = 0; l < m.links.size(); ++l) {
    int parent_joint = -1;
    for (std::size_t j = 0; j < m.joints.size(); ++j)
      if (m.joints[j].child == int(l)) parent_joint = int(j);
    const Joint* pj = parent_joint >= 0 ? &m.joints[std::size_t(parent_joint)] : nullptr;
    const bool moved = pj && pj->type != JointType::Fixed &&
                       (k.chain_slot(parent_joint) >= 0 || (pj->mimic >= 0 && k.chain_slot(pj->mimic) >= 0));
    const bool root_base =
        std::none_of(m.joints.begin(), m.joints.end(), [&](const Joint& j) { return j.child == k.base_link(); });
    if (root_base)
      EXPECT_EQ(k.lanes().frame(int(l)) == int(l), parent_joint < 0 || moved) << "link " << m.links[l].name;
    else EXPECT_EQ(k.lanes().frame(int(l)), int(l)) << "the base is not the root: every link its own frame";
  }
  std::vector<Eigen::Isometry3d> poses;
  test::lane_rounds_on_every_path(k, seed, 60, [&](const std::vector<Eigen::VectorXd>& qs, const double* const* ptr) {
    LinkPoseLanesF frames;
    k.lanes().frame_poses(ptr, frames);
    for (int lane = 0; lane < LinkPoseLanesD::kLanes; ++lane) {
      k.link_poses(qs[std::size_t(lane)], poses);
      for (std::size_t l = 0; l < poses.size(); ++l) {
        const auto& f = frames.pose[std::size_t(k.lanes().frame(int(l)))];
        auto at = [&](int e) { return f[std::size_t(e)][std::size_t(lane)]; };
        for (int axis = 0; axis < 7; ++axis) {
          Eigen::Vector3d p = Eigen::Vector3d::Zero();
          if (axis < 6) p[axis % 3] = axis < 3 ? 0.3 : -0.3;
          const Eigen::Vector3f in_frame = (k.lanes().frame_offset(int(l)) * p).cast<float>();
          Eigen::Vector3d got;
          for (int r = 0; r < 3; ++r)
            got[r] = double(at(3 * r) * in_frame.x() + at(3 * r + 1) * in_frame.y() + at(3 * r + 2) * in_frame.z() +
                            at(9 + r));
          ASSERT_LE((got - poses[l] * p).norm(), k.lanes().float_pose_error(in_frame.cast<double>().norm()))
              << to_string(simd_path()) << " link " << m.links[l].name << " point " << axis;
        }
      }
    }
  });
}

TEST(Kinematics, LaneFramesPlaceEveryLinkWithinTheFloatBound) {
  // A chain with fixed links between its joints (one turned by a quarter, one by no quarter), a
  // joint outside the chain (set), a mimic of a chain joint, and a finger hanging off a fixed hand.
  RobotModel m;
  m.name = "frames";
  for (auto n : {"base", "l1", "adapter", "l2", "bent", "l3", "mimic", "hand", "finger", "wrist"})
    m.links.push_back({n, {}});
  auto joint = [&](const char* name, JointType type, int parent, int child, const Eigen::Vector3d& axis) {
    Joint j;
    j.name = name, j.type = type, j.parent = parent, j.child = child, j.axis = axis.normalized();
    j.lower = type == JointType::Prismatic ? 0.0 : -2.8, j.upper = type == JointType::Prismatic ? 0.04 : 2.8;
    j.origin.translation() = Eigen::Vector3d(0.05 * child, -0.03, 0.1);
    m.joints.push_back(j);
    return std::ref(m.joints.back());
  };
  joint("j1", JointType::Revolute, 0, 1, Eigen::Vector3d::UnitZ());
  joint("fix_a", JointType::Fixed, 1, 2, Eigen::Vector3d::UnitZ()).get().origin.linear() =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  joint("j2", JointType::Revolute, 2, 3, Eigen::Vector3d::UnitY());
  joint("fix_b", JointType::Fixed, 3, 4, Eigen::Vector3d::UnitZ()).get().origin.linear() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  joint("j3", JointType::Revolute, 4, 5, Eigen::Vector3d(0.2, 1, 0.4));
  joint("follows_j3", JointType::Revolute, 5, 6, Eigen::Vector3d::UnitX()).get().mimic = 4;
  joint("hand", JointType::Fixed, 5, 7, Eigen::Vector3d::UnitZ()).get().origin.linear() =
      Eigen::AngleAxisd(-M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  joint("finger", JointType::Prismatic, 7, 8, Eigen::Vector3d::UnitY());
  joint("j4", JointType::Revolute, 7, 9, Eigen::Vector3d::UnitZ());
  Kinematics k(m, "base", "wrist");
  ASSERT_EQ(k.dof(), 4);
  EXPECT_EQ(k.lanes().frame(8), 5) << "the finger rides l3 (through the fixed hand)";
  EXPECT_EQ(k.lanes().frame(4), 3);
  const std::uint64_t before = k.lanes().version;
  k.set_joint_value("finger", 0.03);
  EXPECT_NE(k.lanes().version, before);
  expect_frames_place_every_link(k, 5);
  k.set_joint_value("finger", 0.01);
  expect_frames_place_every_link(k, 6);
  // The built-in arm, its base at the root and not.
  const auto arm = load(test::source_dir() / "datasets/robots/dmgarm/dmgarm.urdf");
  for (const char* base : {"dmgarm_link0", "dmgarm_link2"}) {
    Kinematics a(arm, base, "dmgarm_tcp");
    a.set_joint_value("dmgarm_finger_joint1", 0.021);
    expect_frames_place_every_link(a, 7);
  }
}

// A continuous joint wound far past a turn, or NaN, in some lanes of a lane check: the float
// kinematics' sin and cos leave their core for those (fast_sincos_f8 covers |x| < 1e5). Each lane
// stays within float_pose_error of link_poses, and a NaN lane stays NaN, on both paths.
TEST(Kinematics, FloatLanesHandleWoundAndNanJointsInSomeLanes) {
  RobotModel m;
  m.name = "wound";
  for (int l = 0; l <= 3; ++l) m.links.push_back({"l" + std::to_string(l), {}});
  for (int j = 0; j < 3; ++j) {
    Joint jt;
    jt.name = "j" + std::to_string(j);
    jt.parent = j;
    jt.child = j + 1;
    jt.type = JointType::Continuous;
    jt.origin.translation() = Eigen::Vector3d(0.3, 0.1 * j, 0.05);
    jt.origin.linear() = Eigen::AngleAxisd(0.4 * (j + 1), Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    jt.axis = j == 1 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d(0.6, 0, 0.8);
    m.joints.push_back(jt);
  }
  Kinematics k(m, "l0", "l3");
  const double bound = k.lanes().float_pose_error(0.0);
  std::vector<Eigen::Isometry3d> poses;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    force_simd_path(path);
    for (int wild_lane = 0; wild_lane < LinkPoseLanesD::kLanes; ++wild_lane) {
      std::vector<Eigen::VectorXd> qs;
      const double* ptr[LinkPoseLanesD::kLanes];
      for (int lane = 0; lane < LinkPoseLanesD::kLanes; ++lane) {
        Eigen::VectorXd q = Eigen::Vector3d(0.3 * lane - 1, 2.0 - 0.5 * lane, 0.7 * lane);
        if (lane == wild_lane) q[lane % 3] = lane % 2 ? 3.5e14 + lane : -2.25e5;
        if (lane == (wild_lane + 3) % LinkPoseLanesD::kLanes) q[1] = std::nan("");
        qs.push_back(q);
      }
      for (int lane = 0; lane < LinkPoseLanesD::kLanes; ++lane) ptr[lane] = qs[std::size_t(lane)].data();
      LinkPoseLanesF floats;
      k.lanes().link_poses(ptr, floats);
      for (int lane = 0; lane < LinkPoseLanesD::kLanes; ++lane) {
        const bool nan_lane = std::isnan(qs[std::size_t(lane)][1]);
        if (!nan_lane) k.link_poses(qs[std::size_t(lane)], poses);
        for (std::size_t l = 2; l <= 3; ++l) {  // past the NaN joint
          for (int e = 0; e < 12; ++e) {
            const float got = floats.pose[l][std::size_t(e)][std::size_t(lane)];
            if (nan_lane) {
              if (e < 9) {
                EXPECT_TRUE(std::isnan(got)) << to_string(path) << " lane " << lane << " element " << e;
              }
              continue;
            }
            const double w = e < 9 ? poses[l].linear()(e / 3, e % 3) : poses[l].translation()[e - 9];
            EXPECT_NEAR(got, w, bound) << to_string(path) << " wild lane " << wild_lane << " lane " << lane
                                       << " element " << e;
          }
        }
      }
    }
  }
}

TEST(Kinematics, RejectsChainsThatDoNotExist) {
  EXPECT_THROW(Kinematics(planar_arm(), "base", "nope"), Error);
  EXPECT_THROW(Kinematics(planar_arm(), "tool", "base"), Error);
}

TEST(Kinematics, BuiltInArmJacobianMatchesFiniteDifferencesAndIkRoundTrips) {
  auto m = load(test::source_dir() / "datasets/robots/dmgarm/dmgarm.urdf");
  Kinematics k(m, "dmgarm_link0", "dmgarm_tcp");
  ASSERT_EQ(k.dof(), 7);
  expect_jacobian_matches_finite_differences(k, 50);
  expect_ik_round_trips(k, 200, 0.97);
}

TEST(Kinematics, PandaMatchesItsPublishedZeroPoseAndRoundTrips) {
  DMGPLACE_REQUIRE_SHARED();
  auto root = test::shared_datasets() / "panda";
  auto m = load(root / "moveit_resources_panda_description/urdf/panda.urdf", root);
  Kinematics k(m, "panda_link0", "panda_link8");
  ASSERT_EQ(k.dof(), 7);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(7);
  // The Panda's flange at q = 0 is at (a7, 0, d1 + d3 + d5 - d_flange) = (0.088, 0, 0.926).
  EXPECT_LT((k.tip_pose(q).translation() - Eigen::Vector3d(0.088, 0, 0.926)).norm(), 1e-9);
  expect_jacobian_matches_finite_differences(k, 50);
  expect_ik_round_trips(k, 200, 0.97);
  // Fingers follow their mimic joint: both open by the same amount.
  k.set_joint_value("panda_finger_joint1", 0.03);
  std::vector<Eigen::Isometry3d> poses;
  k.link_poses(q, poses);
  const auto& l = poses[std::size_t(m.link_index("panda_leftfinger"))];
  const auto& r = poses[std::size_t(m.link_index("panda_rightfinger"))];
  EXPECT_NEAR((l.translation() - r.translation()).norm(), 0.06, 1e-9);
}

TEST(Ik, ReportsWhyItFails) {
  Kinematics k(planar_arm(), "base", "tool");
  IkSolver ik(k);
  std::mt19937_64 rng(3);
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() = Eigen::Vector3d(5, 0, 0);
  IkResult r = ik.solve(far, Eigen::VectorXd::Zero(2), rng);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.reason.find("not converged"), std::string::npos);
  Eigen::Isometry3d nan = Eigen::Isometry3d::Identity();
  nan.translation().x() = NAN;
  r = ik.solve(nan, Eigen::VectorXd::Zero(2), rng);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.reason.find("invalid target"), std::string::npos);
}

// fast_sincos against libm over many turns (joint values, their multiples, and the edges of each
// quadrant), and its fallback for huge and non-finite angles.
TEST(FastSincos, AgreesWithLibmToTheLastBits) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-40, 40);
  double worst = 0;
  auto check = [&](double x) {
    double s, c;
    dmgplace::runtime::fast_sincos(x, s, c);
    worst = std::max({worst, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
  };
  for (int i = 0; i < 200000; ++i) check(u(rng));
  for (int k = -40; k <= 40; ++k)
    for (double d : {-1e-12, 0.0, 1e-12}) check(k * M_PI / 4 + d);
  EXPECT_LT(worst, 4e-16);
  double s, c;
  dmgplace::runtime::fast_sincos(1e9, s, c);
  EXPECT_EQ(s, std::sin(1e9));
  dmgplace::runtime::fast_sincos(std::nan(""), s, c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

// fast_sincos_f8 (the AVX2 float lane kinematics' sin and cos): within kSincosF8Error float
// roundoffs of libm over many turns and at every quadrant's edges, compiled both with fused
// multiply-adds (as the AVX2 kinematics run it, where the CPU has them) and without.
static __attribute__((target("avx2,fma"))) void sincos_f8_fma(const double* x, float* s, float* c) {
  dmgplace::runtime::fast_sincos_f8(x, s, c);
}
static void sincos_f8_plain(const double* x, float* s, float* c) { dmgplace::runtime::fast_sincos_f8(x, s, c); }

TEST(FastSincos, FloatsOfEightStayWithinTheirBound) {
  using dmgplace::runtime::kSincosF8Error;
  std::vector<double> x;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-40, 40);
  for (int i = 0; i < (1 << 20); ++i) x.push_back(u(rng));
  for (int k = -160; k <= 160; ++k)
    for (double d : {-1e-7, -1e-12, 0.0, 1e-12, 1e-7}) x.push_back(k * M_PI / 4 + d);
  while (x.size() % 8) x.push_back(0.5);
  const bool fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  for (auto* f : {&sincos_f8_plain, &sincos_f8_fma}) {
    if (f == &sincos_f8_fma && !fma) continue;
    double worst = 0;
    for (std::size_t i = 0; i < x.size(); i += 8) {
      float s[8], c[8];
      f(&x[i], s, c);
      for (std::size_t k = 0; k < 8; ++k)
        worst = std::max({worst, std::abs(s[k] - std::sin(x[i + k])), std::abs(c[k] - std::cos(x[i + k]))});
    }
    worst /= 0x1p-24;
    EXPECT_LE(worst, kSincosF8Error) << (f == &sincos_f8_fma ? "fma" : "plain");
    EXPECT_GT(worst, 0.5) << "floats are rounded: some lane must be off by half a roundoff";
  }
}

// fast_sincos_many (link_poses' joints at once, in SIMD lanes): on both paths, for any count and
// with huge or non-finite angles among them, every lane exactly as fast_sincos answers alone.
TEST(FastSincos, ManyAtOnceEqualsOneAtATimeOnBothPaths) {
  using namespace dmgplace::runtime;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-7, 7);
  int wild_rounds = 0;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    force_simd_path(path);
    for (int n = 0; n <= 40; ++n) {
      std::vector<double> x(static_cast<std::size_t>(n)), s(static_cast<std::size_t>(n), 9.0),
          c(static_cast<std::size_t>(n), 9.0);
      for (auto& v : x) v = u(rng);
      if (n > 3 && n % 3 == 0) {  // one lane past the core's range, one NaN
        x[std::size_t(n / 2)] = n % 2 ? 1e9 : -std::numeric_limits<double>::infinity();
        x[std::size_t(n - 1)] = std::nan("");
        ++wild_rounds;
      }
      fast_sincos_many(x.data(), n, s.data(), c.data());
      for (int k = 0; k < n; ++k) {
        double ws, wc;
        fast_sincos(x[std::size_t(k)], ws, wc);
        if (std::isnan(ws)) {
          EXPECT_TRUE(std::isnan(s[std::size_t(k)]) && std::isnan(c[std::size_t(k)]))
              << to_string(path) << " n " << n << " lane " << k;
          continue;
        }
        EXPECT_EQ(s[std::size_t(k)], ws) << to_string(path) << " n " << n << " lane " << k;
        EXPECT_EQ(c[std::size_t(k)], wc) << to_string(path) << " n " << n << " lane " << k;
      }
    }
  }
  EXPECT_GT(wild_rounds, 10);
}
