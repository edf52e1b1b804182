// The placement search as the paper has it, on the built-in data: the grasp held is the grasp
// used, each grasp's fingers at its own opening, every sample evaluated for the relaxed reward,
// Algorithm 3's cache and draws, and the random-grasp ablation drawing uniformly.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "dmgplace/runtime/grasp/held_grasp.hpp"
#include "dmgplace/runtime/placement/grasp_selector.hpp"
#include "placement_fixture.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using test::side_grasp;
using test::vec;

namespace {
class PlacementSearch : public test::PlacementFixture {
 protected:
  // The pieces Algorithm 3 works on, for the whole cabinet.
  struct Parts {
    SearchSpace space;
    PlacementTree tree;
    ReachableGrasps reach;
    PerGraspCheckers per_grasp;
    Parts(const PlacementWorld& w, const PlacementQuery& q)
        : space(w.object(), w.env().regions, w.env().volume), tree(space, 4, 0.5),
          reach(reachable_grasps(w.grasp_graph(), q.g0)), per_grasp(w, reach.grasps, q.q0) {}
  };
  // A node below the face level under each of two different faces (they share only the root).
  static std::pair<int, int> nodes_under_two_faces(PlacementTree& tree, std::mt19937_64& rng) {
    std::map<int, int> by_face;
    for (int k = 0; k < 4000 && by_face.size() < 2; ++k) {
      const int n = tree.select(rng);
      if (n < 0) break;
      if (tree.node(n).cell.level >= 2) by_face.emplace(tree.node(n).cell.face, n);
      tree.backpropagate(n, 0.5);
    }
    if (by_face.size() < 2) return {-1, -1};
    return {by_face.begin()->second, std::next(by_face.begin())->second};
  }
};

// A hand filter that lets every grasp through.
bool always_free(int, const Eigen::Isometry3d&) { return true; }

// 12 degrees about the approach axis and 1 cm along the bottle: a grasp the DMG does not have.
Eigen::Isometry3d off_grid_side_grasp() {
  return side_grasp() * Eigen::Translation3d(0.01, 0, 0) * Eigen::AngleAxisd(0.21, Eigen::Vector3d::UnitZ());
}
}  // namespace

TEST_F(PlacementSearch, NoRegraspPlacesWithTheGraspActuallyHeld) {
  PlacementQuery qr = query(off_grid_side_grasp());
  qr.variant = PlacementVariant::NoRegrasp;
  const PlacementResult r = solve(qr, 3000, true);
  ASSERT_TRUE(r.solved()) << r.reason;
  EXPECT_GT(r.snap_distance, 0.005) << "g0 is off the DMG's grid";
  const PlacementSolution& s = r.best();
  EXPECT_TRUE(s.grasp.isApprox(qr.g0, 1e-12)) << "the plan must use g0 itself, not its nearest DMG state";
  EXPECT_TRUE(s.in_hand.empty());
  const auto width = grasp_width(world_->object().mesh, qr.g0);
  ASSERT_TRUE(width.has_value());
  EXPECT_NEAR(s.opening, *width, 1e-12);
  EXPECT_NEAR(r.initial_opening, *width, 1e-12);
  // The arm at the end of the path holds the object at its placement through g0.
  const Eigen::Isometry3d held = world_->kinematics().tip_pose(vec(s.path.back())) * qr.g0.inverse();
  EXPECT_LT((held.translation() - s.pose.translation() - Eigen::Vector3d(0, 0, qr.options.lift)).norm(), 1e-3);
}

TEST_F(PlacementSearch, EachGraspsCheckerHasTheFingersAtItsOpening) {
  const auto& fingers = world_->hand().fingers;
  ASSERT_EQ(fingers.size(), 2u);
  const double max_opening = world_->object().dmg.gripper.max_opening;
  auto gap = [&](double opening) {
    // Distance between the two finger frames along the closing axis, from the checker's own
    // kinematics (the state the collision layers pose).
    const TwoLayerChecker c = world_->grasp_checker(side_grasp(), opening, nullptr);
    std::vector<Eigen::Isometry3d> poses;
    const Eigen::VectorXd q = 0.5 * (world_->kinematics().lower() + world_->kinematics().upper());
    c.exact().kinematics().link_poses(q, poses);
    EXPECT_EQ(&c.exact().kinematics(), &c.fast().kinematics());
    const Eigen::Isometry3d tip = poses[std::size_t(world_->kinematics().tip_link())];
    const Eigen::Vector3d a = tip.inverse() * poses[std::size_t(fingers[0])].translation();
    const Eigen::Vector3d b = tip.inverse() * poses[std::size_t(fingers[1])].translation();
    return std::abs(a.y() - b.y());
  };
  const double wide = gap(max_opening), narrow = gap(0.25 * max_opening);
  EXPECT_NEAR(wide - narrow, 0.75 * max_opening, 1e-9);
  // The hand filter of Algorithm 3 sees the same fingers.
  double hand_gap = 0;
  for (const auto& [link, pose] : world_->hand_at(0.25 * max_opening))
    if (link == fingers[0]) hand_gap += pose.translation().y();
    else if (link == fingers[1]) hand_gap -= pose.translation().y();
  EXPECT_NEAR(std::abs(hand_gap), narrow, 1e-9);
  // And a planned grasp's space uses its own opening from the DMG.
  const PlacementQuery qr = query(side_grasp());
  Parts p(*world_, qr);
  for (int g : {1, p.per_grasp.size() / 2, p.per_grasp.size() - 1}) {
    const double opening = p.per_grasp.grasp(g).opening;
    EXPECT_NEAR(opening, world_->grasp_graph().opening(p.per_grasp.grasp(g).state), 1e-12);
    std::vector<Eigen::Isometry3d> poses;
    p.per_grasp.checker(g)->exact().kinematics().link_poses(
        0.5 * (world_->kinematics().lower() + world_->kinematics().upper()), poses);
    const Eigen::Isometry3d tip = poses[std::size_t(world_->kinematics().tip_link())];
    const double y = std::abs((tip.inverse() * poses[std::size_t(fingers[0])].translation()).y() -
                              (tip.inverse() * poses[std::size_t(fingers[1])].translation()).y());
    EXPECT_NEAR(wide - y, max_opening - std::clamp(opening, 0.0, max_opening), 1e-9) << "grasp " << g;
  }
}

TEST_F(PlacementSearch, EverySampleIsEvaluatedForReachability) {
  // The relaxed reward needs the IK answer of samples that are unstable, colliding or not
  // improving too: with the paper's Algorithm 3 (hand_tries 0) every sample gets a grasp and an
  // IK call.
  PlacementQuery qr = query(side_grasp());
  qr.options.hand_tries = 0;
  const PlacementResult r = solve(qr, 400);
  const PlacementCounters& c = r.counters;
  ASSERT_GT(c.samples, 50);
  EXPECT_EQ(c.ik_calls, c.samples);
  EXPECT_LT(c.stable, c.samples) << "some samples are unstable and were still evaluated";
  EXPECT_GT(c.reachable, c.goals) << "kinematically reachable samples that are not goals feed the reward and the cache";
  EXPECT_GT(c.cached_grasps, 0);
}

TEST_F(PlacementSearch, AnEmptyCacheStillRollsPAccept) {
  const PlacementQuery qr = query(side_grasp());
  Parts p(*world_, qr);
  std::mt19937_64 rng(1);
  const auto [a, b] = nodes_under_two_faces(p.tree, rng);
  ASSERT_GE(a, 0);
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  GraspSelector never(p.per_grasp, p.tree, PlacementVariant::Full, 0.0, 8, always_free);
  for (int k = 0; k < 50; ++k) {
    const GraspChoice c = never.select(a, pose, rng);
    EXPECT_FALSE(c.cached);
    EXPECT_NE(c.grasp, 0) << "p_accept = 0: g0 is never taken as the empty cache's stand-in, the draw excludes it";
    EXPECT_GE(c.grasp, 0);
  }
  GraspSelector always(p.per_grasp, p.tree, PlacementVariant::Full, 1.0, 8, always_free);
  const GraspChoice c = always.select(a, pose, rng);
  EXPECT_EQ(c.grasp, 0);
  EXPECT_TRUE(c.cached);
}

TEST_F(PlacementSearch, ACachedGraspThatNeverReachesBelowANodeIsOfferedLessThere) {
  const PlacementQuery qr = query(side_grasp());
  Parts p(*world_, qr);
  std::mt19937_64 rng(3);
  const auto [a, b] = nodes_under_two_faces(p.tree, rng);
  ASSERT_GE(b, 0);
  const int up = p.tree.node(a).parent;
  ASSERT_GE(p.tree.node(up).parent, 0) << "a's parent is below the root";
  const int g = p.per_grasp.size() - 1;
  GraspSelector s(p.per_grasp, p.tree, PlacementVariant::Full, 1.0, 8, always_free);
  s.cache(a, g);
  EXPECT_EQ(s.acceptance(a, g), 1.0) << "no record: the paper's p_accept";
  // A record above a node counts there until the node has its own: the nearest one wins.
  s.record(up, g, false);
  EXPECT_DOUBLE_EQ(s.acceptance(a, g), 0.5);
  for (int k = 0; k < 99; ++k) s.record(a, g, false);
  EXPECT_DOUBLE_EQ(s.acceptance(a, g), 0.01) << "99 tries at a, none reached";
  EXPECT_DOUBLE_EQ(s.acceptance(up, g), 1.0 / 101) << "a's 99 and up's own one";
  EXPECT_EQ(s.acceptance(b, g), 1.0) << "records do not cross the root";
  int cached = 0;
  for (int k = 0; k < 300; ++k) cached += s.select(a, Eigen::Isometry3d::Identity(), rng).cached;
  EXPECT_LT(cached, 30) << "grasps outside the cache are drawn where the cached one never reaches";
  s.record(a, g, true);
  EXPECT_EQ(s.acceptance(a, g), 1.0) << "a grasp that reached here at all keeps the paper's p_accept";
  for (int k = 0; k < 50; ++k) EXPECT_TRUE(s.select(a, Eigen::Isometry3d::Identity(), rng).cached);
  GraspSelector random(p.per_grasp, p.tree, PlacementVariant::RandomGrasp, 1.0, 8, always_free);
  random.record(a, g, false);
  EXPECT_EQ(random.acceptance(a, g), 1.0) << "only full keeps records";
}

TEST_F(PlacementSearch, CachedGraspsAreFoundFromTheNodeUpButNotThroughTheRoot) {
  const PlacementQuery qr = query(side_grasp());
  Parts p(*world_, qr);
  std::mt19937_64 rng(2);
  const auto [a, b] = nodes_under_two_faces(p.tree, rng);
  ASSERT_GE(b, 0);
  GraspSelector s(p.per_grasp, p.tree, PlacementVariant::Full, 1.0, 8, always_free);
  const int g = p.per_grasp.size() - 1;
  s.cache(a, g);
  s.cache(a, g);  // a set: no repeats
  EXPECT_EQ(s.cached(a), std::vector<int>{g});
  EXPECT_EQ(s.cached(p.tree.node(a).parent), std::vector<int>{g}) << "propagated to the ancestors";
  EXPECT_TRUE(s.cached(b).empty()) << "only the root is shared, and the root's cache is not read";
  EXPECT_EQ(s.select(a, Eigen::Isometry3d::Identity(), rng).grasp, g);
  EXPECT_EQ(s.select(b, Eigen::Isometry3d::Identity(), rng).grasp, 0);
  // The hand filter applies to cached grasps: with every hand colliding, the cached grasp is
  // skipped and the draw (the paper's, unchecked) comes from the rest of G(g0).
  GraspSelector blocked(p.per_grasp, p.tree, PlacementVariant::Full, 1.0, 0,
                        [](int, const Eigen::Isometry3d&) { return false; });
  blocked.cache(a, g);
  for (int k = 0; k < 30; ++k) {
    const GraspChoice c = blocked.select(a, Eigen::Isometry3d::Identity(), rng);
    EXPECT_NE(c.grasp, g);
    EXPECT_FALSE(c.cached);
  }
}

TEST_F(PlacementSearch, RandomGraspDrawsUniformlyFromTheReachableGrasps) {
  const PlacementQuery qr = query(side_grasp());
  Parts p(*world_, qr);
  int usable = 0;
  for (int g = 0; g < p.per_grasp.size(); ++g) usable += p.per_grasp.usable(g);
  ASSERT_GT(usable, 20);
  // Not hand-filtered: the ablation of the paper draws even where every hand would collide.
  GraspSelector s(p.per_grasp, p.tree, PlacementVariant::RandomGrasp, 0.9, 8,
                  [](int, const Eigen::Isometry3d&) { return false; });
  std::mt19937_64 rng(4);
  std::vector<int> count(std::size_t(p.per_grasp.size()), 0);
  const int draws = 200 * usable;
  for (int k = 0; k < draws; ++k) {
    const GraspChoice c = s.select(0, Eigen::Isometry3d::Identity(), rng);
    ASSERT_GE(c.grasp, 0);
    ASSERT_TRUE(p.per_grasp.usable(c.grasp));
    ++count[std::size_t(c.grasp)];
  }
  // Pearson's chi-square against uniform over the usable grasps, well inside its tail.
  const double expected = double(draws) / usable;
  double chi2 = 0;
  for (int g = 0; g < p.per_grasp.size(); ++g)
    if (p.per_grasp.usable(g))
      chi2 += (count[std::size_t(g)] - expected) * (count[std::size_t(g)] - expected) / expected;
  const double dof = usable - 1;
  EXPECT_LT(chi2, dof + 6 * std::sqrt(2 * dof));
  EXPECT_GT(chi2, dof - 6 * std::sqrt(2 * dof)) << "too even to be random";
}

TEST_F(PlacementSearch, HandTriesZeroIsThePapersDrawAndOtherwiseDrawsAreHandChecked) {
  const PlacementQuery qr = query(side_grasp());
  Parts p(*world_, qr);
  std::mt19937_64 rng(6);
  const auto [a, b] = nodes_under_two_faces(p.tree, rng);
  ASSERT_GE(a, 0);
  int checks = 0;
  const auto blocked = [&](int, const Eigen::Isometry3d&) { return ++checks, false; };
  GraspSelector paper(p.per_grasp, p.tree, PlacementVariant::Full, 0.9, 0, blocked);
  paper.select(a, Eigen::Isometry3d::Identity(), rng);
  EXPECT_EQ(checks, 1) << "only G = {g0} is hand-checked";
  checks = 0;
  GraspSelector filtered(p.per_grasp, p.tree, PlacementVariant::Full, 0.9, 5, blocked);
  const GraspChoice c = filtered.select(a, Eigen::Isometry3d::Identity(), rng);
  EXPECT_EQ(checks, 1 + 5) << "g0, then five hand-checked draws";
  EXPECT_EQ(c.grasp, -1) << "no hand fits: no grasp (and no IK)";
  // With hands that fit, the first hand-checked draw is taken.
  checks = 0;
  GraspSelector fits(p.per_grasp, p.tree, PlacementVariant::Full, 0.0, 5,
                     [&](int, const Eigen::Isometry3d&) { return ++checks, true; });
  EXPECT_GE(fits.select(a, Eigen::Isometry3d::Identity(), rng).grasp, 1);
  EXPECT_EQ(checks, 2);
}
