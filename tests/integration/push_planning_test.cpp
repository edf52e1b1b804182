// The in-hand actions planned for a second arm (issue 60, part 2): the built-in dual-arm robot
// dmgdual, the bottle held top-down (only a regrasp places it deep on the cabinet's lower shelf)
// and its pushes checked as a robot would execute them.
#include <gtest/gtest.h>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/grasp/held_grasp.hpp"
#include "dmgplace/runtime/motion/arm_timing.hpp"
#include "dmgplace/runtime/motion/segment_check.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"
#include "dmgplace/runtime/placement/push_planner.hpp"
#include "dmgplace/tools/placement/placement_query_file.hpp"
#include "placement_fixture.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace dmgplace::test {
namespace {

class PushPlanning : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    set_up_suite_or_exit("PushPlanning", [] {
      dir_ = new TempDir();
      const auto d = dir_->path();
      const auto data = source_dir() / "datasets";
      ASSERT_EQ(
          run_cli({"bake-robot", data / "robots/dmgdual/dmgdual.urdf", "--srdf", data / "robots/dmgdual/dmgdual.srdf",
                   "--joint-limits", data / "robots/dmgdual/joint_limits.yaml", "--arm", "dmgarm_link0:dmgarm_tcp",
                   "--out", d / "dual.h5"})
              .exit_code,
          0);
      ASSERT_EQ(run_cli({"make-objects", "--out", d}).exit_code, 0);
      ASSERT_EQ(run_cli({"bake-object", d / "bottle.stl", "--mass", "0.15", "--out", d / "bottle.h5"}).exit_code, 0);
      ASSERT_EQ(run_cli({"bake-env", data / "scenes/cabinet.yaml", "--volume", builtin_volume("cabinet"), "--margin",
                         "0.9", "--sdf-resolution", "0.02", "--band", "0.25", "--out", d / "cabinet.h5"})
                    .exit_code,
                0);
      // The pusher parked turned back, as datasets/queries/dual_cabinet_bottle_blocked.yaml has it.
      std::map<std::string, double> park{{"pusher_joint1", 2.9},    {"pusher_joint2", -0.785}, {"pusher_joint3", 0},
                                         {"pusher_joint4", -2.356}, {"pusher_joint5", 0},      {"pusher_joint6", 1.571},
                                         {"pusher_joint7", 0.785}};
      world_ = new runtime::PlacementWorld(formats::load_robot(d / "dual.h5"), formats::load_object(d / "bottle.h5"),
                                           formats::load_environment(d / "cabinet.h5"), -1, park);
    });
  }
  static void TearDownTestSuite() {
    delete world_;
    delete dir_;
  }
  static runtime::PlacementQuery query() {
    runtime::PlacementQuery q;
    q.q0 = Eigen::VectorXd(7);
    q.q0 << 0.9, -0.785, 0, -2.356, 0, 1.571, 0.785;  // turned towards the pusher
    q.g0 = top_grasp();
    q.volume = Eigen::AlignedBox3d(Eigen::Vector3d(0.62, -0.07, 0.45), Eigen::Vector3d(0.85, 0.39, 0.72));
    q.seed = 1;
    runtime::PusherSpec p;
    p.base = "dmgarm_link0";
    p.tip = "pusher_tcp";
    q.pusher = p;
    return q;
  }
  static runtime::PlacementResult solve(const runtime::PlacementQuery& q) {
    runtime::PlacementPlanner planner(*world_, q);
    bool found = false;
    auto budget = runtime::stop_after_iterations(20000);
    return planner.run([&] { return found || budget(); }, [&](const runtime::PlacementSolution&) { found = true; });
  }
  static inline TempDir* dir_ = nullptr;
  static inline runtime::PlacementWorld* world_ = nullptr;
};

TEST_F(PushPlanning, EveryPushIsACollisionFreeMotionThatCarriesTheContactWithTheObject) {
  const runtime::PlacementQuery q = query();
  const auto r = solve(q);
  ASSERT_TRUE(r.solved()) << r.reason;
  const auto& best = r.best();
  ASSERT_FALSE(best.in_hand.empty());  // g0 cannot place it
  ASSERT_EQ(best.pushes.size(), best.in_hand.size());
  EXPECT_EQ(r.pusher_joints.size(), 7u);
  EXPECT_GT(r.counters.push_plans, 0);

  const runtime::PushPlanner pusher(*world_, *q.pusher, q.q0, q.options.motion_resolution, q.seed, "test");
  const runtime::Kinematics& kin = pusher.kinematics();
  const auto limits = runtime::arm_joint_limits(kin);
  const auto& graph = world_->grasp_graph();
  for (std::size_t i = 0; i < best.pushes.size(); ++i) {
    const auto& p = best.pushes[i];
    const auto& a = best.in_hand[i];
    EXPECT_EQ(p.action, int(i));
    ASSERT_GE(p.path.size(), 3u);
    // From the pusher's start and back to it, within its limits.
    EXPECT_LT((vec(p.path.front()) - pusher.start()).norm(), 1e-12);
    EXPECT_LT((vec(p.path.back()) - pusher.start()).norm(), 1e-12);
    for (const auto& w : p.path) EXPECT_TRUE(kin.within_limits(vec(w), 1e-9));
    // The grasp after the action is the DMG's, and the object's poses are where the grasping arm
    // (at q0) holds it at each grasp.
    EXPECT_TRUE(p.grasp_after.isApprox(graph.tcp_pose(a.to_state), 1e-12));
    const Eigen::Isometry3d tcp = world_->kinematics().tip_pose(q.q0);
    EXPECT_TRUE((p.object_before * graph.tcp_pose(a.from_state)).isApprox(tcp, 1e-9));
    EXPECT_TRUE((p.object_after * p.grasp_after).isApprox(tcp, 1e-9));
    // The tool touches the object at the contact and, through the push, stays on the point of the
    // object it touched (the contact carried by the object's motion).
    ASSERT_GE(p.push_begin, 1);
    ASSERT_GT(p.push_end, p.push_begin);
    ASSERT_LT(std::size_t(p.push_end), p.path.size());
    const Eigen::Vector3d on_object = p.object_before.inverse() * p.contact;
    EXPECT_LT((pusher.tcp_pose(vec(p.path[std::size_t(p.push_begin)])).translation() - p.contact).norm(), 2e-4);
    EXPECT_LT((pusher.tcp_pose(vec(p.path[std::size_t(p.push_end)])).translation() - p.object_after * on_object).norm(),
              2e-4);
    EXPECT_LT(runtime::surface_distance(world_->object().mesh, on_object), 1e-9);
    // Away from the push, no part of the pusher touches the object (at either pose), the scene or
    // the rest of the robot: every segment at the motion resolution.
    // The grasping fingers at the action's opening, as the planner holds them.
    runtime::Kinematics held(kin);
    const double opening = std::max(graph.opening(a.from_state), graph.opening(a.to_state));
    const auto& m = kin.model();
    for (std::size_t j = 0; j < m.joints.size(); ++j)
      if (m.joints[j].type != JointType::Fixed && m.joints[j].mimic < 0 && kin.chain_slot(int(j)) < 0)
        held.set_joint_value(m.joints[j].name, world_->kinematics_at(opening).joint_value(int(j), q.q0));
    const runtime::ExactChecker base(held, world_->scene());
    for (const bool before : {true, false}) {
      const Eigen::Isometry3d& object = before ? p.object_before : p.object_after;
      const runtime::ExactChecker strict =
          base.with_attached(world_->object_mesh(), kin.base_link(), object, world_->hand().links);
      const runtime::ValidityFn free = [&](const Eigen::VectorXd& x) { return strict.is_free(x); };
      // The tool's last and first half of the standoff are in the push's zone (push_planner.hpp).
      const int half = int(std::ceil(q.pusher->standoff / q.pusher->step)) / 2 + 1;
      const std::size_t from = before ? 0 : std::size_t(p.push_end + half),
                        to = before ? std::size_t(p.push_begin - half) : p.path.size() - 1;
      for (std::size_t k = from; k < to; ++k)
        EXPECT_TRUE(runtime::segment_valid(vec(p.path[k]), vec(p.path[k + 1]), q.options.motion_resolution, free))
            << "push " << i << " segment " << k << " of " << p.path.size() << " (push " << p.push_begin << ".."
            << p.push_end << "): " << strict.check(vec(p.path[k + 1])).contact;
    }
    // Timed within the pusher's limits.
    ASSERT_FALSE(p.trajectory.empty());
    for (std::size_t s = 0; s < p.trajectory.time.size(); ++s)
      for (std::size_t j = 0; j < limits.velocity.size(); ++j) {
        EXPECT_LE(std::abs(p.trajectory.velocities[s][j]), limits.velocity[j] * (1 + 1e-6));
        EXPECT_LE(std::abs(p.trajectory.accelerations[s][j]), limits.acceleration[j] * (1 + 1e-6));
      }
  }
}

TEST_F(PushPlanning, WithoutAPusherTheSameQueryReportsTheActionsUnplanned) {
  runtime::PlacementQuery q = query();
  q.pusher.reset();
  const auto r = solve(q);
  ASSERT_TRUE(r.solved()) << r.reason;
  EXPECT_TRUE(r.best().pushes.empty());
  EXPECT_TRUE(r.pusher_joints.empty());
  EXPECT_EQ(r.counters.push_plans, 0);
}

TEST_F(PushPlanning, APusherThatCannotBeOneIsRefusedNamingTheQueryAndElement) {
  const auto refused = [&](auto change, const std::string& element, const std::string& why) {
    runtime::PlacementQuery q = query();
    q.source = "dual.yaml";
    change(q);
    const std::string e = error_of([&] { runtime::PlacementPlanner(*world_, q); });
    EXPECT_NE(e.find("dual.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find(element), std::string::npos) << e;
    EXPECT_NE(e.find(why), std::string::npos) << e;
  };
  refused([](auto& q) { q.pusher->tip = "dmgarm_tcp"; }, "pusher.arm", "grasping arm");
  refused([](auto& q) { q.pusher->tip = "no_such_link"; }, "pusher.arm", "no link 'no_such_link'");
  refused([](auto& q) { q.pusher->base = "pusher_link2"; }, "pusher.arm", "rigid");
  refused([](auto& q) { q.pusher->tcp.translation().x() = std::nan(""); }, "pusher.tcp", "not finite");
  refused([](auto& q) { q.pusher->standoff = 0; }, "pusher.standoff", "must be in");
  refused([](auto& q) { q.pusher->plan_time = std::nan(""); }, "pusher.plan_time", "must be in");
}

TEST_F(PushPlanning, AQueryFileNamesThePusherAndBadValuesAreRefusedThere) {
  const auto d = dir_->path();
  const std::string head =
      "robot: dual.h5\nobject: bottle.h5\nenvironment: cabinet.h5\nstart: [0.9, -0.785, 0, -2.356, 0, 1.571, 0.785]\n"
      "initial_grasp: {pose: [0, 0, 0.13, 1, 0, 0, 0]}\n";
  write_text(d / "q.yaml",
             head + "pusher: {arm: dmgarm_link0:pusher_tcp, tcp: [0, 0, 0.01, 0, 0, 0, 1], standoff: 0.04}\n");
  const auto q = tools::read_placement_query(d / "q.yaml");
  ASSERT_TRUE(q.query.pusher);
  EXPECT_EQ(q.query.pusher->base, "dmgarm_link0");
  EXPECT_EQ(q.query.pusher->tip, "pusher_tcp");
  EXPECT_NEAR(q.query.pusher->tcp.translation().z(), 0.01, 1e-15);
  EXPECT_DOUBLE_EQ(q.query.pusher->standoff, 0.04);
  for (const auto& [text, element] : std::vector<std::pair<std::string, std::string>>{
           {"pusher: {arm: pusher_tcp}", "pusher.arm"},
           {"pusher: {arm: a:b:c}", "pusher.arm"},
           {"pusher: {tcp: [0, 0, 0, 0, 0, 0, 1]}", "pusher"},
           {"pusher: {arm: a:b, tcp: [0, 0, .nan, 0, 0, 0, 1]}", "pusher.tcp"},
           {"pusher: {arm: a:b, standoff: 0}", "pusher.standoff"},
           {"pusher: {arm: a:b, plan_iterations: 0}", "pusher.plan_iterations"},
           {"pusher: {arm: a:b, reach: 2}", "reach"}}) {
    write_text(d / "bad.yaml", head + text + "\n");
    const std::string e = error_of([&] { tools::read_placement_query(d / "bad.yaml"); });
    EXPECT_NE(e.find("bad.yaml"), std::string::npos) << text << ": " << e;
    EXPECT_NE(e.find(element), std::string::npos) << text << ": " << e;
  }
}

}  // namespace
}  // namespace dmgplace::test
