// QUERY.yaml of `dmgplace place`: a good file reads, and every broken one is a dmgplace::Error
// naming the file, the element and the reason (never a crash, never a NaN passed to the planner).
#include "dmgplace/tools/placement/placement_query_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

using test::error_of;
using test::TempDir;
using test::write_text;
using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kArtifacts = "robot: arm.h5\nobject: bottle.h5\nenvironment: cabinet.h5\n";
const std::string kStart = "start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]\n";
const std::string kGrasp = "initial_grasp: {pose: [0, 0, 0.06, 0, 0.7071068, 0, 0.7071068]}\n";

runtime::Kinematics dmgarm() {
  return runtime::Kinematics(read_urdf(test::source_dir() / "datasets/robots/dmgarm/dmgarm.urdf"), "dmgarm_link0",
                             "dmgarm_tcp");
}

TEST(PlacementQueryFile, ReadsAGoodQuery) {
  TempDir dir;
  write_text(dir / "q.yaml", kArtifacts + kStart + kGrasp +
                                 "volume: [0.5, -0.4, 0.4, 0.9, 0.4, 1.1]\ntime_limit: 0\nvariant: no-regrasp\n"
                                 "options: {ucb_c: 2}\n");
  const auto q = read_placement_query(dir / "q.yaml");
  EXPECT_EQ(q.robot, dir / "arm.h5");
  EXPECT_EQ(q.time_limit, 0);
  EXPECT_EQ(q.query.variant, runtime::PlacementVariant::NoRegrasp);
  EXPECT_EQ(q.query.options.ucb_c, 2);
  ASSERT_TRUE(q.query.volume.has_value());
  EXPECT_EQ(resolve_start(q, dmgarm()).size(), 7);
}

// Each broken file: the element the message must name and the reason it must give.
struct Broken {
  const char* name;
  std::string yaml;
  const char* element;
  const char* reason;
};

TEST(PlacementQueryFile, BrokenQueriesNameTheFileAndTheProblem) {
  const Broken cases[] = {
      {"missing robot", "object: b.h5\nenvironment: c.h5\n" + kStart + kGrasp, "robot", "missing"},
      {"missing start", kArtifacts + kGrasp, "start", "missing"},
      {"missing grasp", kArtifacts + kStart, "initial_grasp", "missing"},
      {"NaN in start list", kArtifacts + "start: [0, -0.785, .nan, -2.356, 0, 1.571, 0.785]\n" + kGrasp, "start[2]",
       "not a finite number"},
      {"infinity in named start", kArtifacts + "start: {dmgarm_joint1: .inf}\n" + kGrasp, "start.dmgarm_joint1",
       "not a finite number"},
      {"short pose", kArtifacts + kStart + "initial_grasp: {pose: [0, 0, 0.06, 0, 0, 1]}\n", "initial_grasp.pose",
       "expected a list of 7 numbers"},
      {"NaN in pose", kArtifacts + kStart + "initial_grasp: {pose: [0, 0, .nan, 0, 0, 0, 1]}\n", "initial_grasp.pose",
       "not a finite number"},
      {"zero quaternion", kArtifacts + kStart + "initial_grasp: {pose: [0, 0, 0, 0, 0, 0, 0]}\n", "initial_grasp.pose",
       "zero quaternion"},
      {"unknown variant", kArtifacts + kStart + kGrasp + "variant: best\n", "variant", "unknown variant 'best'"},
      {"negative time limit", kArtifacts + kStart + kGrasp + "time_limit: -1\n", "time_limit",
       "outside its range [0, "},
      {"NaN time limit", kArtifacts + kStart + kGrasp + "time_limit: .nan\n", "time_limit", "not a finite number"},
      // Issue 19: limits that overflowed or hung, keys that were ignored.
      {"time limit past a nanosecond count", kArtifacts + kStart + kGrasp + "time_limit: 1e12\n", "time_limit",
       "outside its range"},
      {"IK restarts without end", kArtifacts + kStart + kGrasp + "options: {ik_restarts: 2000000000}\n",
       "options.ik_restarts", "outside its range [0, 1000]"},
      {"a hundred thousand threads", kArtifacts + kStart + kGrasp + "options: {threads: 100000}\n", "options.threads",
       "outside its range [0, 256]"},
      {"fractional count", kArtifacts + kStart + kGrasp + "options: {goal_iterations: 2.5}\n",
       "options.goal_iterations", "expected an integer"},
      {"unknown top-level key", kArtifacts + kStart + kGrasp + "tme_limit: 3\n", "tme_limit (line 6)", "unknown key"},
      {"typo in a term", kArtifacts + kStart + kGrasp + "objective: [{term: clearance, wieght: 2}]\n",
       "objective[0].wieght", "unknown key"},
      {"duplicate key", kArtifacts + kStart + kGrasp + "seed: 1\nseed: 2\n", "line 7", "duplicate key 'seed'"},
      {"duplicate nested key",
       kArtifacts + kStart + "initial_grasp: {pose: [0, 0, 0, 0, 0, 0, 1], opening: 0.05, opening: 0.06}\n", "line 5",
       "duplicate key 'opening'"},
      {"negative opening", kArtifacts + kStart + "initial_grasp: {pose: [0, 0, 0.06, 0, 0, 0, 1], opening: -0.02}\n",
       "initial_grasp.opening", "outside its range"},
      {"unknown grasp key", kArtifacts + kStart + "initial_grasp: {pose: [0, 0, 0.06, 0, 0, 0, 1], width: 0.02}\n",
       "initial_grasp.width", "unknown key"},
      {"vector of another term",
       kArtifacts + kStart + kGrasp + "objective: [{term: clearance, direction: [1, 0, 0]}]\n",
       "objective[0].direction", "does not belong to term 'clearance'"},
      {"zero depth direction", kArtifacts + kStart + kGrasp + "objective: [{term: depth, direction: [0, 0, 0]}]\n",
       "objective[0].direction", "non-zero"},
      {"volume in another galaxy", kArtifacts + kStart + kGrasp + "volume: [0, 0, 0, 1e300, 1, 1]\n", "volume",
       "beyond"},
      {"inverted volume", kArtifacts + kStart + kGrasp + "volume: [1, 1, 1, 0, 0, 0]\n", "volume", "min exceeds max"},
      {"NaN option", kArtifacts + kStart + kGrasp + "options: {ucb_c: .nan}\n", "options.ucb_c", "not a finite number"},
      {"unknown option", kArtifacts + kStart + kGrasp + "options: {speed: 2}\n", "options.speed", "unknown option"},
      {"NaN weight", kArtifacts + kStart + kGrasp + "objective: [{term: clearance, weight: .nan}]\n",
       "objective[0].weight", "not a finite number"},
      {"text for a number", kArtifacts + kStart + kGrasp + "seed: many\n", "line 6", "malformed query"},
      {"not a map", "- 1\n- 2\n", "", "expected a map"},
  };
  TempDir dir;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto path = dir / "broken.yaml";
    write_text(path, c.yaml);
    EXPECT_THAT(error_of([&] { read_placement_query(path); }),
                AllOf(HasSubstr(path.string()), HasSubstr(c.element), HasSubstr(c.reason)));
  }
}

// resolve_start is the second gate: the arm's joint count and limits.
TEST(PlacementQueryFile, StartsThatDoNotFitTheArmAreRejected) {
  TempDir dir;
  const auto kin = dmgarm();
  const auto path = dir / "q.yaml";
  write_text(path, kArtifacts + "start: [0, 0, 0]\n" + kGrasp);
  EXPECT_THAT(error_of([&] { resolve_start(read_placement_query(path), kin); }),
              AllOf(HasSubstr(path.string()), HasSubstr("has 3 values, the arm has 7 joints")));
  write_text(path, kArtifacts + "start: {dmgarm_joint1: 0}\n" + kGrasp);
  EXPECT_THAT(error_of([&] { resolve_start(read_placement_query(path), kin); }),
              AllOf(HasSubstr(path.string()), HasSubstr("no value for joint 'dmgarm_joint2'")));
  write_text(path, kArtifacts + "start: [0, 0, 10, 0, 0, 0, 0]\n" + kGrasp);
  EXPECT_THAT(error_of([&] { resolve_start(read_placement_query(path), kin); }),
              AllOf(HasSubstr(path.string()), HasSubstr("outside the arm's joint limits")));
  // Issue 21: a named joint outside the chain, or no joint at all, is not silently ignored.
  const std::string arm =
      "dmgarm_joint1: 0, dmgarm_joint2: -0.785, dmgarm_joint3: 0, dmgarm_joint4: -2.356, "
      "dmgarm_joint5: 0, dmgarm_joint6: 1.571, dmgarm_joint7: 0.785";
  write_text(path, kArtifacts + "start: {" + arm + "}\n" + kGrasp);
  EXPECT_EQ(resolve_start(read_placement_query(path), kin).size(), 7);
  // A joint outside the chain goes to the world (world_joint_values); a world without it is refused.
  write_text(path, kArtifacts + "start: {" + arm + ", dmgarm_finger_joint1: 0.02}\n" + kGrasp);
  const auto q = read_placement_query(path);
  RobotModel model = kin.model();  // as a robot artifact has it: with its arm chain named
  model.arm_base = "dmgarm_link0";
  model.arm_tip = "dmgarm_tcp";
  EXPECT_EQ(world_joint_values(q, model), (std::map<std::string, double>{{"dmgarm_finger_joint1", 0.02}}));
  EXPECT_THAT(error_of([&] { resolve_start(q, kin); }),
              AllOf(HasSubstr(path.string()), HasSubstr("start.dmgarm_finger_joint1"),
                    HasSubstr("world was built without it")));
  runtime::Kinematics set = kin;
  set.set_joint_value("dmgarm_finger_joint1", 0.02);
  EXPECT_EQ(resolve_start(q, set).size(), 7);
  write_text(path, kArtifacts + "start: {" + arm + ", elbow_of_the_other_arm: 1}\n" + kGrasp);
  EXPECT_THAT(error_of([&] { resolve_start(read_placement_query(path), kin); }),
              AllOf(HasSubstr(path.string()), HasSubstr("no joint of that name")));
  EXPECT_THAT(error_of([&] { world_joint_values(read_placement_query(path), model); }),
              AllOf(HasSubstr(path.string()), HasSubstr("start.elbow_of_the_other_arm")));
}

// Issue 19: an artifact path may not lead out of the artifact folder (`..`, absolute, symlink).
TEST(PlacementQueryFile, ArtifactPathsStayInTheArtifactFolder) {
  TempDir dir;
  std::filesystem::create_directories(dir / "artifacts");
  const auto path = dir / "artifacts" / "q.yaml";
  const std::string rest = "object: bottle.h5\nenvironment: cabinet.h5\n" + kStart + kGrasp;
  write_text(path, "robot: ../../../../../../etc/passwd\n" + rest);
  EXPECT_THAT(error_of([&] { read_placement_query(path); }),
              AllOf(HasSubstr(path.string()), HasSubstr("robot"), HasSubstr("outside the artifact folder"),
                    HasSubstr("--allow-outside")));
  write_text(path, "robot: /etc/passwd\n" + rest);
  EXPECT_THAT(error_of([&] { read_placement_query(path); }), HasSubstr("outside the artifact folder"));
  std::filesystem::create_symlink("/etc", dir / "artifacts" / "link");
  write_text(path, "robot: link/passwd\n" + rest);
  EXPECT_THAT(error_of([&] { read_placement_query(path); }), HasSubstr("outside the artifact folder"));
  // Inside is fine, also through `..` that comes back in; --allow-outside lets the others through.
  write_text(path, "robot: sub/../arm.h5\n" + rest);
  EXPECT_EQ(read_placement_query(path).robot, dir / "artifacts" / "sub/../arm.h5");
  write_text(path, "robot: /etc/passwd\n" + rest);
  EXPECT_EQ(read_placement_query(path, {}, true).robot, "/etc/passwd");
  // With --artifacts, that folder is the root, not the query's.
  write_text(path, "robot: ../artifacts/arm.h5\n" + rest);
  EXPECT_THAT(error_of([&] { read_placement_query(path, dir / "other"); }), HasSubstr("outside the artifact folder"));
}

// Every option of the runtime's table is readable by name and refused outside its range.
TEST(PlacementQueryFile, EveryOptionHasItsRangeEnforced) {
  TempDir dir;
  const auto path = dir / "q.yaml";
  for (const auto& spec : runtime::placement_option_specs()) {
    SCOPED_TRACE(spec.name);
    if (std::holds_alternative<bool runtime::PlacementOptions::*>(spec.member)) {
      write_text(path, kArtifacts + kStart + kGrasp + "options: {" + spec.name + ": maybe}\n");
      EXPECT_THAT(error_of([&] { read_placement_query(path); }), HasSubstr("expected true or false"));
      continue;
    }
    const bool integer = std::holds_alternative<int runtime::PlacementOptions::*>(spec.member);
    const auto num = [&](double v) {
      char b[40];
      std::snprintf(b, sizeof b, integer ? "%.0f" : "%.17g", v);
      return std::string(b);
    };
    const double above = spec.hi + (integer ? 1 : std::max(1e-3, spec.hi * 0.01));
    write_text(path, kArtifacts + kStart + kGrasp + "options: {" + spec.name + ": " + num(above) + "}\n");
    EXPECT_THAT(error_of([&] { read_placement_query(path); }),
                AllOf(HasSubstr(path.string()), HasSubstr(std::string("options.") + spec.name),
                      HasSubstr("outside its range")));
    // The range's ends are accepted.
    for (double v : {spec.lo, spec.hi}) {
      write_text(path, kArtifacts + kStart + kGrasp + "options: {" + spec.name + ": " + num(v) + "}\n");
      EXPECT_NO_THROW(read_placement_query(path)) << v;
    }
  }
}

}  // namespace
}  // namespace dmgplace::tools
