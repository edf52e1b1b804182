// Issue 19: crafted artifacts with consistent checksums (a buggy writer, another tool, a future
// version) meet the loaders' semantic gate, never the runtime. Sound artifacts of the built-in
// data are baked in-process, then >= 100 copies are made with one element changed and its SHA-256
// recomputed: targeted ones that once crashed, hung or ran to a wrong answer, and seeded random
// ones. Each must be either refused with an error that names the file, or load and run a short
// placement query without a crash. A hang fails through ctest's timeout.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "artifact_mutation.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/grasp/reachable_grasps.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"
#include "sound_artifacts.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {

using Sound = test::SoundArtifacts;

enum class Kind { Robot, Object, Environment };

struct Mutation {
  std::string label;  // for the failure message
  Kind kind;
  std::string dataset;
  std::size_t index;
  double value;
  bool must_refuse;  // the targeted ones: each once crashed, hung or gave a wrong answer
};

// What happened to one crafted file.
enum class Outcome { Refused, Ran };

Outcome try_file(const Sound& s, const Mutation& m, const fs::path& crafted) {
  (void)formats::validate_artifact(crafted);  // must not crash either
  const fs::path robot = m.kind == Kind::Robot ? crafted : s.robot;
  const fs::path object = m.kind == Kind::Object ? crafted : s.object;
  const fs::path env = m.kind == Kind::Environment ? crafted : s.env;
  try {
    runtime::PlacementWorld world(formats::load_robot(robot), formats::load_object(object),
                                  formats::load_environment(env));
    runtime::PlacementQuery q;
    q.q0 = Eigen::VectorXd(7);
    q.q0 << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
    q.g0 = Eigen::Translation3d(0, 0, 0.0175) * Eigen::Quaterniond(0, 1, 0, 0);  // top-down on the eraser
    q.seed = 1;
    q.options.optimize_locally = false;
    (void)runtime::reachable_grasps(world.grasp_graph(), q.g0);
    runtime::PlacementPlanner planner(world, q);
    (void)planner.run(runtime::stop_after_iterations(20), [](const runtime::PlacementSolution&) {});
    return Outcome::Ran;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(crafted.string()), std::string::npos)
        << m.label << ": the error does not name the file: " << message;
    return Outcome::Refused;
  }
}

std::vector<Mutation> targeted(const Sound& s) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double region_height = test::dataset_value(s.env, "regions/scalars", 0);
  return {
      {"regions raised 10 cm (a placement in mid-air)", Kind::Environment, "regions/scalars", 0, region_height + 0.1,
       true},
      {"region resolution 0", Kind::Environment, "regions/scalars", 4, 0, true},
      {"sdf resolution 0 (Grid3 needs a positive resolution)", Kind::Environment, "fields/sdf/grid", 3, 0, true},
      {"clearance band NaN", Kind::Environment, "fields/clearance/grid", 4, nan, true},
      {"volume 1e300", Kind::Environment, "volume", 3, 1e300, true},
      {"scene box 1e300", Kind::Environment, "scene/shapes/size", 0, 1e300, true},
      {"scene shape zero quaternion", Kind::Environment, "scene/shapes/pose", 6, 0,
       false},  // w only: the rest may still be a rotation
      {"DMG edge index out of range (SIGSEGV)", Kind::Object, "dmg/edges", 0, 1e6, true},
      {"DMG angle step 0 (SIGFPE)", Kind::Object, "dmg/settings", 0, 0, true},
      {"DMG angle step 1e-6 (2.3 GB per query)", Kind::Object, "dmg/settings", 0, 1e-6, true},
      {"DMG node angle count 2^31-1", Kind::Object, "dmg/node_indices", 4, 2147483647, true},
      {"DMG node facet -5", Kind::Object, "dmg/node_indices", 1, -5, true},
      {"DMG patch count NaN", Kind::Object, "dmg/settings", 3, nan, true},
      {"placement face margin NaN", Kind::Object, "placement/faces", 7, nan, true},
      {"placement face height NaN", Kind::Object, "placement/faces", 8, nan, true},
      {"placement face height +10 cm", Kind::Object, "placement/faces", 8,
       test::dataset_value(s.object, "placement/faces", 8) + 0.1, true},
      {"gripper opening NaN", Kind::Object, "dmg/gripper", 0, nan, true},
      {"mass NaN", Kind::Object, "mass/volume_mass", 1, nan, true},
      {"joint axis NaN", Kind::Robot, "joints/values", 7, nan, true},
      {"joint velocity NaN", Kind::Robot, "joints/values", 12, nan, true},
      {"mimic multiplier NaN", Kind::Robot, "joints/values", 13, nan, false},  // joint 0 may not mimic
      {"mimic of itself", Kind::Robot, "joints/indices", 3, 0, true},
      {"joint parent out of range", Kind::Robot, "joints/indices", 1, 1000, true},
      {"sphere radius -1", Kind::Robot, "links/spheres", 3, -1, true},
      {"collision box 1e9 m", Kind::Robot, "links/collision/size", 0, 1e9, true},
      {"self table slope NaN", Kind::Robot, "self_tables/grid", 2, nan, true},
  };
}

}  // namespace

TEST(CraftedArtifacts, NoCrashNoHangEveryRejectionNamesTheFile) {
  const auto s = test::bake_sound_artifacts();
  ASSERT_EQ(try_file(*s, {"sound", Kind::Object, "", 0, 0, false}, s->object), Outcome::Ran)
      << "the sound artifacts must run";

  std::vector<Mutation> all = targeted(*s);
  // Seeded random ones: any dataset of any artifact, any element, a hostile value.
  std::mt19937_64 rng(20261202);
  const double hostile[] = {std::numeric_limits<double>::quiet_NaN(),
                            std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity(),
                            0,
                            -1,
                            1e300,
                            -1e300,
                            2147483647,
                            -2147483648.0,
                            1e-300};
  for (int i = 0; i < 110; ++i) {
    const Kind kind = Kind(rng() % 3);
    const fs::path& base = kind == Kind::Robot ? s->robot : kind == Kind::Object ? s->object : s->env;
    const auto names = test::artifact_datasets(base);
    const std::string& name = names[rng() % names.size()];
    const std::size_t n = test::dataset_size(base, name);
    if (n == 0) continue;
    const std::size_t index = rng() % n;
    double value = hostile[rng() % std::size(hostile)];
    if (rng() % 3 == 0)
      value = test::dataset_value(base, name, index) * (rng() % 2 ? 1.5 : -1) + 0.01;  // plausible but wrong
    all.push_back(
        {name + "[" + std::to_string(index) + "] = " + std::to_string(value), kind, name, index, value, false});
  }
  ASSERT_GE(all.size(), 100u);

  int refused = 0, ran = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Mutation& m = all[i];
    SCOPED_TRACE(m.label);
    const fs::path& base = m.kind == Kind::Robot ? s->robot : m.kind == Kind::Object ? s->object : s->env;
    const fs::path crafted = s->dir / ("crafted_" + std::to_string(i) + ".h5");
    test::mutate_dataset(base, crafted, m.dataset, m.index, m.value);
    const Outcome o = try_file(*s, m, crafted);
    if (m.must_refuse) {
      EXPECT_EQ(o, Outcome::Refused) << m.label << " was accepted";
    }
    (o == Outcome::Refused ? refused : ran)++;
    fs::remove(crafted);
  }
  std::printf("crafted artifacts: %zu files, %d refused naming the file, %d loaded and ran, 0 crashes\n", all.size(),
              refused, ran);
}
