// Issue 19, items 5, 6 and 8 through `dmgplace place`, as a user meets them: a grasp far from the
// object, artifact paths that leave the artifact folder, and every refusal naming the query file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;
using ::testing::AllOf;
using ::testing::HasSubstr;

namespace {

class QueryGate : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    test::set_up_suite_or_exit("QueryGate", [] { bake(); });
  }
  static void TearDownTestSuite() { delete dir_; }
  static void bake() {
    dir_ = new test::TempDir();
    const fs::path data = test::source_dir() / "datasets", d = artifacts();
    fs::create_directories(d);
    for (const std::vector<test::Arg>& args :
         {std::vector<test::Arg>{"make-objects", "--out", d},
          {"bake-object", d / "eraser.stl", "--out", d / "eraser.h5"},
          {"bake-robot", data / "robots/dmgarm/dmgarm.urdf", "--srdf", data / "robots/dmgarm/dmgarm.srdf", "--arm",
           "dmgarm_link0:dmgarm_tcp", "--out", d / "arm.h5"},
          {"bake-env", data / "scenes/table.yaml", "--volume", "0.3,-0.3,0.4,0.8,0.3,0.7", "--resolution", "0.02",
           "--margin", "0.9", "--sdf-resolution", "0.04", "--band", "0.25", "--out", d / "table.h5"}}) {
      const auto r = test::run_cli(args);
      ASSERT_EQ(r.exit_code, 0) << r.output;
    }
  }
  static fs::path artifacts() { return dir_->path() / "artifacts"; }
  // A query in the artifact folder: the eraser held top-down on the table.
  static fs::path query(const std::string& grasp, const std::string& robot = "arm.h5") {
    const fs::path q = artifacts() / "q.yaml";
    test::write_text(q,
                     "robot: " + robot +
                         "\nobject: eraser.h5\nenvironment: table.h5\nstart: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]\n"
                         "initial_grasp: " +
                         grasp + "\ntime_limit: 1\n");
    return q;
  }
  static test::TempDir* dir_;
};
test::TempDir* QueryGate::dir_ = nullptr;

TEST_F(QueryGate, AGraspFarFromTheObjectIsRefusedWithItsDistance) {
  const auto q = query("{pose: [10, 0, 0.0175, 1, 0, 0, 0]}");
  const auto r = test::run_cli({"place", q, "--out", dir_->path() / "out_far"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output,
              AllOf(HasSubstr(q.string()), HasSubstr("initial_grasp"), HasSubstr("m from the object's surface")));
  EXPECT_FALSE(fs::exists(dir_->path() / "out_far" / "result.json"));
  // The same grasp on the object runs (and writes its result).
  const auto ok =
      test::run_cli({"place", query("{pose: [0, 0, 0.0175, 1, 0, 0, 0]}"), "--out", dir_->path() / "out_ok"});
  EXPECT_TRUE(ok.exit_code == 0 || ok.exit_code == 3) << ok.output;
  EXPECT_TRUE(fs::exists(dir_->path() / "out_ok" / "result.json"));
}

TEST_F(QueryGate, AnOpeningWiderThanTheGripperIsRefused) {
  const auto q = query("{pose: [0, 0, 0.0175, 1, 0, 0, 0], opening: 0.5}");
  const auto r = test::run_cli({"place", q, "--out", dir_->path() / "out_wide"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, AllOf(HasSubstr("eraser.h5"), HasSubstr("exceeds the gripper's maximum")));
}

TEST_F(QueryGate, ArtifactPathsOutsideTheFolderNeedAllowOutside) {
  // A copy of the robot one folder up: reachable only through `..`.
  fs::copy_file(artifacts() / "arm.h5", dir_->path() / "arm_outside.h5", fs::copy_options::overwrite_existing);
  const auto q = query("{pose: [0, 0, 0.0175, 1, 0, 0, 0]}", "../arm_outside.h5");
  const auto refused = test::run_cli({"place", q, "--time-limit", "0.2", "--out", dir_->path() / "out_outside"});
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_THAT(refused.output, AllOf(HasSubstr(q.string()), HasSubstr("outside the artifact folder")));
  const auto allowed =
      test::run_cli({"place", q, "--allow-outside", "--time-limit", "0.2", "--out", dir_->path() / "out_outside"});
  EXPECT_TRUE(allowed.exit_code == 0 || allowed.exit_code == 3) << allowed.output;
}

}  // namespace
