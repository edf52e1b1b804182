// Robots without an SRDF: the allowed-collision pairs decided as MoveIt's setup assistant does
// include every pair a hand-reviewed SRDF disables as Adjacent or Never, leave the robot's ready
// pose free of self-collision, and round-trip through the SRDF written for review.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <set>
#include <sstream>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/robot/allowed_collisions.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {

struct Robot {
  fs::path urdf, srdf;
  std::vector<fs::path> packages;
  std::string base, tip;
};

RobotModel model_without_srdf(const Robot& r) {
  tools::UrdfOptions o;
  o.package_paths = r.packages;
  RobotModel m = tools::read_urdf(r.urdf, o);
  tools::set_arm_chain(m, r.base, r.tip, r.urdf.string());
  return m;
}

// The SRDF's pairs with the given reasons (read back through apply_srdf on a copy).
std::set<std::pair<int, int>> srdf_pairs(const RobotModel& m, const fs::path& srdf,
                                         const std::set<std::string>& reasons) {
  // apply_srdf keeps no reasons: filter the file's lines by reason, write them out, read back.
  std::string kept = "<robot name=\"" + m.name + "\">\n";
  std::istringstream in(test::read_text(srdf));
  for (std::string line; std::getline(in, line);)
    if (line.find("<disable_collisions") != std::string::npos)
      for (const auto& r : reasons)
        if (line.find("reason=\"" + r + "\"") != std::string::npos) kept += line + "\n";
  kept += "</robot>\n";
  test::TempDir dir;
  formats::write_file_atomically(dir / "kept.srdf", kept);
  RobotModel copy = m;
  copy.allowed_pairs.clear();
  tools::apply_srdf(copy, dir / "kept.srdf");
  return {copy.allowed_pairs.begin(), copy.allowed_pairs.end()};
}

void check_robot(const Robot& r, const Eigen::VectorXd& ready) {
  const RobotModel m = model_without_srdf(r);
  const tools::AllowedCollisions decided = tools::compute_allowed_collisions(m);
  std::set<std::pair<int, int>> disabled;
  for (const auto& p : decided.disabled) {
    EXPECT_LT(p.a, p.b);
    disabled.insert({p.a, p.b});
  }
  // Every pair the reviewed SRDF disables as Adjacent or Never is disabled here too, unless a
  // sampled configuration showed it colliding (then checking it is the safe side): the
  // difference is listed.
  std::string kept_checked;
  for (const auto& [a, b] : srdf_pairs(m, r.srdf, {"Adjacent", "Never"})) {
    if (disabled.count({a, b})) continue;
    const auto it = std::find_if(decided.checked.begin(), decided.checked.end(),
                                 [&](const auto& c) { return c.a == a && c.b == b; });
    ASSERT_NE(it, decided.checked.end()) << m.links[std::size_t(a)].name << "/" << m.links[std::size_t(b)].name;
    EXPECT_GT(it->collisions, 0);
    kept_checked += " " + m.links[std::size_t(a)].name + "/" + m.links[std::size_t(b)].name + " (collided in " +
                    std::to_string(it->collisions) + " of " + std::to_string(decided.samples) + ")";
  }
  std::cout << "pairs the SRDF disables that stay checked:" << (kept_checked.empty() ? " none" : kept_checked) << "\n";
  EXPECT_EQ(int(decided.disabled.size() + decided.checked.size()), decided.checked_pairs);
  // Adjacent pairs are found as adjacent.
  for (const auto& [a, b] : srdf_pairs(m, r.srdf, {"Adjacent"}))
    for (const auto& p : decided.disabled)
      if (p.a == a && p.b == b) {
        EXPECT_EQ(p.reason, tools::DisableReason::Adjacent)
            << m.links[std::size_t(a)].name << "/" << m.links[std::size_t(b)].name;
      }
  // With the decided pairs the ready pose is free of self-collision (without them it is not).
  RobotModel with = m;
  for (const auto& p : decided.disabled) with.allowed_pairs.emplace_back(p.a, p.b);
  const runtime::Kinematics kin_with(with, with.arm_base, with.arm_tip), kin_without(m, m.arm_base, m.arm_tip);
  EXPECT_TRUE(runtime::ExactChecker(kin_with, Scene{}).is_free(ready));
  EXPECT_FALSE(runtime::ExactChecker(kin_without, Scene{}).is_free(ready))
      << "adjacent links touch: nothing to decide?";
  // Deterministic, and the SRDF written for review reads back as the same pairs.
  const tools::AllowedCollisions again = tools::compute_allowed_collisions(m);
  ASSERT_EQ(again.disabled.size(), decided.disabled.size());
  test::TempDir dir;
  formats::write_file_atomically(dir / "review.srdf", tools::srdf_text(m, decided.disabled));
  RobotModel back = m;
  tools::apply_srdf(back, dir / "review.srdf");
  const std::set<std::pair<int, int>> read_back(back.allowed_pairs.begin(), back.allowed_pairs.end());
  EXPECT_EQ(read_back, disabled);
}

}  // namespace

TEST(AllowedCollisions, DmgarmWithoutItsSrdfGetsItsPairsAndAFreeHome) {
  const fs::path d = test::source_dir() / "datasets/robots/dmgarm";
  Eigen::VectorXd home(7);
  home << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  check_robot({d / "dmgarm.urdf", d / "dmgarm.srdf", {}, "dmgarm_link0", "dmgarm_tcp"}, home);
}

TEST(AllowedCollisions, PandaWithoutItsSrdfGetsItsPairsAndAFreeReadyPose) {
  DMGPLACE_REQUIRE_SHARED();
  const fs::path p = test::shared_datasets() / "panda";
  Eigen::VectorXd ready(7);
  ready << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  check_robot({p / "moveit_resources_panda_description/urdf/panda.urdf",
               p / "panda_moveit_config/config/panda.srdf",
               {p},
               "panda_link0",
               "panda_hand"},
              ready);
}

// dmgdual without its SRDF, planned for its grasping arm: the pusher arm (dmgarm's links and joints
// again, named pusher_*) is sampled too, so a pair of its links that collides as often as the same
// pair of the grasping arm is checked as that one is (sampling only the planning chain left every
// pusher pair "never colliding", and so unchecked, whatever the pusher later did).
TEST(AllowedCollisions, EveryArmIsSampledNotOnlyThePlanningChain) {
  const fs::path d = test::source_dir() / "datasets/robots/dmgdual";
  const RobotModel m = model_without_srdf({d / "dmgdual.urdf", d / "dmgdual.srdf", {}, "dmgarm_link0", "dmgarm_tcp"});
  const tools::AllowedCollisions decided = tools::compute_allowed_collisions(m);
  auto checked = [&](const std::string& a, const std::string& b) -> int {
    const int la = m.link_index(a), lb = m.link_index(b);
    for (const auto& c : decided.checked)
      if ((c.a == la && c.b == lb) || (c.a == lb && c.b == la)) return c.collisions;
    return 0;
  };
  int compared = 0;
  for (int x = 0; x <= 7; ++x)
    for (int y = x + 2; y <= 7; ++y) {
      const std::string gx = "dmgarm_link" + std::to_string(x), gy = "dmgarm_link" + std::to_string(y);
      if (m.link_index(gx) < 0 || m.link_index(gy) < 0 || checked(gx, gy) < decided.samples / 100) continue;
      ++compared;
      EXPECT_GT(checked("pusher_link" + std::to_string(x), "pusher_link" + std::to_string(y)), 0)
          << gx << "/" << gy << " collided in " << checked(gx, gy) << " of " << decided.samples;
    }
  EXPECT_GT(compared, 0) << "no pair of the grasping arm collides often enough to compare";
}
