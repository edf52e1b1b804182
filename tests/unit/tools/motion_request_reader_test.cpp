// MotionPlanRequest YAML: joint values must be finite numbers; a NaN or infinity in the start
// state or a goal is an error naming the file and the joint, never a value handed to the planner.
#include "dmgplace/tools/io/motion_request_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

using test::error_of;
using test::TempDir;
using test::write_text;
using ::testing::AllOf;
using ::testing::HasSubstr;

std::string request(const std::string& start_b, const std::string& goal_a) {
  return "start_state:\n  joint_state:\n    name: [a, b]\n    position: [0.5, " + start_b +
         "]\n"
         "goal_constraints:\n  - joint_constraints:\n      - {joint_name: a, position: " +
         goal_a + "}\n      - {joint_name: b, position: 0.0}\n";
}

TEST(MotionRequest, ReadsFiniteJointValues) {
  TempDir dir;
  write_text(dir / "r.yaml", request("-1.5e-3", "1.0"));
  const auto r = read_motion_request(dir / "r.yaml");
  EXPECT_EQ(r.start.at("b"), -1.5e-3);
  EXPECT_EQ(r.goal.at("a"), 1.0);
}

TEST(MotionRequest, NonFiniteJointValuesAreRejected) {
  TempDir dir;
  const auto path = dir / "r.yaml";
  for (const char* bad : {".nan", ".NaN", ".inf", "-.inf"}) {
    SCOPED_TRACE(bad);
    write_text(path, request(bad, "1.0"));
    EXPECT_THAT(
        error_of([&] { read_motion_request(path); }),
        AllOf(HasSubstr(path.string()), HasSubstr("start_state.joint_state.b"), HasSubstr("not a finite number")));
    write_text(path, request("0.0", bad));
    EXPECT_THAT(error_of([&] { read_motion_request(path); }),
                AllOf(HasSubstr(path.string()), HasSubstr("goal joint a"), HasSubstr("not a finite number")));
  }
}

}  // namespace
}  // namespace dmgplace::tools
