#pragma once
// The placement planner's integration fixture: the built-in cabinet, dmgarm and bottle, baked
// through the CLI once per test process, then driven through the C++ API.
#include <gtest/gtest.h>

#include <memory>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace dmgplace::test {

// Top-down grasp near the bottle's top: placing it upright deep on the lower shelf would put the
// hand and wrist into the shelf above, so only an in-hand regrasp can place it there.
inline Eigen::Isometry3d top_grasp() { return Eigen::Translation3d(0, 0, 0.13) * Eigen::Quaterniond(0, 1, 0, 0); }
inline Eigen::Isometry3d side_grasp() {
  return Eigen::Translation3d(0, 0, 0.06) * Eigen::Quaterniond(0.7071068, 0, 0.7071068, 0);
}
inline Eigen::VectorXd vec(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

class PlacementFixture : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    set_up_suite_or_exit("Placement", [] { bake(); });
  }
  static void bake() {
    namespace fs = std::filesystem;
    // `dmgplace ARGS...`'s exit code; its output is not needed.
    auto cli = [](const std::vector<Arg>& args) { return run_cli(args, false).exit_code; };
    dir_ = new TempDir();
    const fs::path data = source_dir() / "datasets";
    const fs::path d = dir_->path();
    ASSERT_EQ(cli({"make-objects", "--out", d}), 0);
    ASSERT_EQ(cli({"bake-robot", data / "robots/dmgarm/dmgarm.urdf", "--srdf", data / "robots/dmgarm/dmgarm.srdf",
                   "--joint-limits", data / "robots/dmgarm/joint_limits.yaml", "--arm", "dmgarm_link0:dmgarm_tcp",
                   "--out", d / "arm.h5"}),
              0);
    ASSERT_EQ(cli({"bake-object", d / "bottle.stl", "--mass", "0.15", "--out", d / "bottle.h5"}), 0);
    const std::string volume = builtin_volume("cabinet");
    ASSERT_EQ(cli({"bake-env", data / "scenes/cabinet.yaml", "--volume", volume, "--margin", "0.9", "--sdf-resolution",
                   "0.02", "--band", "0.25", "--out", d / "cabinet.h5"}),
              0);
    world_ = new runtime::PlacementWorld(formats::load_robot(d / "arm.h5"), formats::load_object(d / "bottle.h5"),
                                         formats::load_environment(d / "cabinet.h5"));
  }
  static void TearDownTestSuite() {
    delete world_;
    delete dir_;
  }

  static runtime::PlacementQuery query(const Eigen::Isometry3d& g0) {
    runtime::PlacementQuery qr;
    qr.q0 = Eigen::VectorXd(7);
    qr.q0 << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
    qr.g0 = g0;
    qr.seed = 3;
    return qr;
  }
  // Lower shelf, right of the compartment, from 7 cm behind the cabinet's front edge.
  static Eigen::AlignedBox3d deep_lower_shelf() {
    return {Eigen::Vector3d(0.62, -0.07, 0.45), Eigen::Vector3d(0.85, 0.39, 0.72)};
  }

  static runtime::PlacementResult solve(const runtime::PlacementQuery& qr, long iterations, bool until_first = false) {
    runtime::PlacementPlanner planner(*world_, qr);
    bool found = false;
    auto budget = runtime::stop_after_iterations(iterations);
    return planner.run([&] { return (until_first && found) || budget(); },
                       [&](const runtime::PlacementSolution&) { found = true; });
  }

  static inline TempDir* dir_ = nullptr;
  static inline runtime::PlacementWorld* world_ = nullptr;
};

}  // namespace dmgplace::test
