// Timed trajectories end to end on the built-in cabinet: every published solution's approach and
// retreat are timed within the arm's limits (velocities from dmgarm.urdf, accelerations from its
// joint_limits.yaml), and `place`/`plan` write them as JSON and MoveIt JointTrajectory YAML.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include "dmgplace/runtime/motion/arm_timing.hpp"
#include "placement_fixture.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {
using test::side_grasp;
class TimedTrajectory : public test::PlacementFixture {};

// Limits held at every sample, ends at rest on the path's ends.
void expect_executable(const Trajectory& t, const JointPath& path, const JointLimits& limits, double scaling) {
  ASSERT_FALSE(t.empty());
  ASSERT_EQ(t.positions.size(), t.time.size());
  for (std::size_t j = 0; j < path.front().size(); ++j) {
    EXPECT_NEAR(t.positions.front()[j], path.front()[j], 1e-9);
    EXPECT_NEAR(t.positions.back()[j], path.back()[j], 1e-9);
    EXPECT_NEAR(t.velocities.front()[j], 0, 1e-9);
    EXPECT_NEAR(t.velocities.back()[j], 0, 1e-9);
  }
  for (std::size_t k = 0; k < t.time.size(); ++k) {
    if (k) {
      EXPECT_GT(t.time[k], t.time[k - 1]);
    }
    for (std::size_t j = 0; j < path.front().size(); ++j) {
      EXPECT_LE(std::abs(t.velocities[k][j]), limits.velocity[j] * scaling * (1 + 1e-6) + 1e-9) << "sample " << k;
      EXPECT_LE(std::abs(t.accelerations[k][j]), limits.acceleration[j] * scaling * (1 + 1e-6) + 1e-9)
          << "sample " << k;
    }
  }
}
}  // namespace

TEST_F(TimedTrajectory, LimitsComeFromTheUrdfAndTheJointLimitsFile) {
  const JointLimits limits = arm_joint_limits(world_->kinematics());
  ASSERT_EQ(limits.velocity.size(), 7u);
  EXPECT_DOUBLE_EQ(limits.velocity[0], 2.3925);     // dmgarm.urdf
  EXPECT_DOUBLE_EQ(limits.acceleration[1], 1.875);  // joint_limits.yaml
  EXPECT_DOUBLE_EQ(limits.acceleration[6], 5.0);
}

TEST_F(TimedTrajectory, EverySolutionIsTimedWithinTheLimits) {
  for (double scaling : {1.0, 0.3}) {
    SCOPED_TRACE("scaling " + std::to_string(scaling));
    PlacementQuery qr = query(side_grasp());
    qr.options.velocity_scaling = qr.options.acceleration_scaling = scaling;
    const PlacementResult r = solve(qr, 1500, true);
    ASSERT_TRUE(r.solved()) << r.reason;
    const JointLimits limits = arm_joint_limits(world_->kinematics());
    for (const auto& s : r.improvements) {
      expect_executable(s.trajectory, s.path, limits, scaling);
      if (!s.retreat.empty()) expect_executable(s.retreat_trajectory, s.retreat, limits, scaling);
    }
  }
}

TEST_F(TimedTrajectory, PlaceAndPlanWriteJsonAndMoveItYaml) {
  const fs::path d = dir_->path();
  test::write_text(d / "side.yaml",
                   "robot: arm.h5\nobject: bottle.h5\nenvironment: cabinet.h5\n"
                   "start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]\n"
                   "initial_grasp: {pose: [0, 0, 0.06, 0, 0.7071068, 0, 0.7071068]}\n"
                   "options: {velocity_scaling: 0.5}\n");
  const auto place = test::run_cli({"place", d / "side.yaml", "--iterations", "1500", "--time-limit", "60", "--out",
                                    d / "side", "--trajectory-format", "moveit"});
  ASSERT_EQ(place.exit_code, 0) << place.output;
  const auto j = nlohmann::json::parse(test::read_text(d / "side/trajectory.json"));
  const auto result = nlohmann::json::parse(test::read_text(d / "side/result.json"));
  ASSERT_EQ(j["joint_names"].size(), 7u);
  const auto& approach = j["approach"];
  ASSERT_GT(approach["time"].size(), 1u);
  EXPECT_EQ(approach["positions"].front(), result["best"]["path"].front());
  EXPECT_DOUBLE_EQ(approach["duration"].get<double>(), result["best"]["duration"].get<double>());
  // The MoveIt file is the same trajectory as a trajectory_msgs/JointTrajectory.
  const YAML::Node y = YAML::LoadFile((d / "side/trajectory_approach.yaml").string());
  ASSERT_EQ(y["joint_names"].size(), 7u);
  EXPECT_EQ(y["joint_names"][0].as<std::string>(), j["joint_names"][0].get<std::string>());
  ASSERT_EQ(y["points"].size(), approach["time"].size());
  const YAML::Node last = y["points"][y["points"].size() - 1];
  const double t = last["time_from_start"]["sec"].as<double>() + last["time_from_start"]["nanosec"].as<double>() * 1e-9;
  EXPECT_NEAR(t, approach["duration"].get<double>(), 1e-9);
  EXPECT_NEAR(last["positions"][3].as<double>(), approach["positions"].back()[3].get<double>(), 1e-12);
  EXPECT_TRUE(fs::exists(d / "side/trajectory_retreat.yaml"));

  const fs::path data = test::source_dir() / "datasets";
  const auto plan =
      test::run_cli({"plan", data / "scenes/cabinet.yaml", data / "requests/cabinet_reach.yaml", "--robot",
                     d / "arm.h5", "--out", d / "reach.json", "--trajectory-format", "moveit"});
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  const auto p = nlohmann::json::parse(test::read_text(d / "reach.json"));
  EXPECT_EQ(p["trajectory"]["positions"].back(), p["waypoints"].back());
  EXPECT_EQ(YAML::LoadFile((d / "reach.trajectory.yaml").string())["points"].size(), p["trajectory"]["time"].size());
  const auto bad = test::run_cli({"plan", data / "scenes/cabinet.yaml", data / "requests/cabinet_reach.yaml", "--robot",
                                  d / "arm.h5", "--trajectory-format", "moveit"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("needs --out"), std::string::npos) << bad.output;
}
