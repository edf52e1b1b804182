// Issue 61: `validate --deep` holds an artifact's numbers against its own exact geometry. Sound
// artifacts pass; five physically wrong ones, each with consistent checksums and each passing the
// ordinary validation, are refused with a message naming the file, the dataset and the worst
// sample.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/tools/robot/bake_robot.hpp"
#include "dmgplace/tools/validate/deep_validation.hpp"
#include "run_cli.hpp"
#include "sound_artifacts.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {

const test::SoundArtifacts& sound() {
  static const auto s = test::bake_sound_artifacts();
  return *s;
}

tools::DeepOptions with_inputs() {
  tools::DeepOptions o;
  o.check_inputs = true;
  return o;
}

// The forged file passes the ordinary validation, and --deep refuses it naming the file and the
// dataset, with the worst sample's values.
void expect_refused(const fs::path& forged, const std::string& dataset, const tools::DeepOptions& o = {}) {
  ASSERT_TRUE(formats::validate_artifact(forged).empty())
      << "a forgery the ordinary validation already refuses: " << formats::validate_artifact(forged).front();
  const auto report = tools::deep_validate(forged, o);
  EXPECT_FALSE(report.ok());
  const auto problems = report.problems();
  ASSERT_FALSE(problems.empty());
  bool named = false;
  for (const auto& p : problems)
    named |=
        p.find(forged.string()) == 0 && p.find(dataset) != std::string::npos && p.find(" at ") != std::string::npos;
  EXPECT_TRUE(named) << problems.front();
}

// A copy of a sound artifact changed by `edit` and saved with consistent checksums.
template <class Edit>
fs::path forged_env(const std::string& name, Edit edit) {
  auto env = formats::read_environment_unchecked(sound().env);
  edit(env);
  const fs::path out = sound().dir / (name + ".h5");
  formats::save_environment(std::move(env), out);
  return out;
}
template <class Edit>
fs::path forged_robot(const std::string& name, Edit edit) {
  auto robot = formats::read_robot_unchecked(sound().robot);
  edit(robot);
  const fs::path out = sound().dir / (name + ".h5");
  formats::save_robot(std::move(robot), out);
  return out;
}

}  // namespace

TEST(DeepValidation, SoundArtifactsPassEveryCheck) {
  for (const auto& f : {sound().robot, sound().object, sound().env}) {
    const auto report = tools::deep_validate(f, with_inputs());
    EXPECT_FALSE(report.checks.empty()) << f;
    for (const auto& c : report.checks) {
      EXPECT_TRUE(c.ok()) << f << ": " << tools::describe(c);
      EXPECT_GT(c.samples, 0) << c.name;
    }
  }
}

TEST(DeepValidation, SameSeedSameReport) {
  tools::DeepOptions o;
  o.samples = 200;
  o.seed = 5;
  const auto a = tools::deep_validate(sound().env, o), b = tools::deep_validate(sound().env, o);
  ASSERT_EQ(a.checks.size(), b.checks.size());
  for (std::size_t i = 0; i < a.checks.size(); ++i) {
    EXPECT_EQ(a.checks[i].worst, b.checks[i].worst);
    EXPECT_EQ(a.checks[i].worst_sample, b.checks[i].worst_sample);
  }
}

static void negate_field(formats::EnvironmentArtifact& env) {
  for (auto& v : env.sdf.values) v = -v;
}

TEST(DeepValidation, RefusesANegatedDistanceField) {
  expect_refused(forged_env("negated_field", negate_field), "fields/sdf/values");
}

TEST(DeepValidation, RefusesSceneShapesShrunkAgainstTheirField) {
  int shrunk = 0;
  const auto forged = forged_env("shrunk_scene", [&](formats::EnvironmentArtifact& env) {
    for (auto& o : env.scene.objects)
      for (auto& s : o.shapes)
        if (s.type != ShapeType::Mesh) s.size *= 0.97, ++shrunk;
  });
  ASSERT_GT(shrunk, 0);
  expect_refused(forged, "fields/sdf/values");
}

TEST(DeepValidation, RefusesRobotSpheresThatNoLongerCoverTheLinks) {
  // The bake inflates each sphere by its sample spacing beyond the farthest sample: without that
  // and 1% less, the spheres leave link surface points outside.
  const double spacing = tools::RobotBakeOptions{}.spheres.sample_spacing;
  const auto sound_report = tools::deep_validate(sound().robot);
  EXPECT_LT(sound_report.checks.at(0).worst, 0) << "a sound cover reports its margin as a negative worst";
  const auto forged = forged_robot("shrunk_spheres", [&](formats::RobotArtifact& robot) {
    for (auto& s : robot.spheres) s.radius = (s.radius - spacing) * 0.99;
  });
  expect_refused(forged, "links/spheres");
}

TEST(DeepValidation, RefusesASelfDistanceTableRaisedByOneMetre) {
  bool raised = false;
  const auto forged = forged_robot("raised_table", [&](formats::RobotArtifact& robot) {
    if (robot.self_tables.empty()) return;
    for (auto& d : robot.self_tables[0].distance) d += 1.0f;
    raised = true;
  });
  ASSERT_TRUE(raised);
  expect_refused(forged, "self_tables/distance");
}

TEST(DeepValidation, RefusesJointLimitsWiderThanTheUrdf) {
  int widened = 0;
  const auto forged = forged_robot("wide_limits", [&](formats::RobotArtifact& robot) {
    for (auto& j : robot.model.joints)
      if (j.type == JointType::Revolute && widened == 0) j.upper += 0.3, ++widened;
  });
  ASSERT_EQ(widened, 1);
  expect_refused(forged, "joints/values", with_inputs());
  // Without the URDF at hand nothing says the limits are wrong: --deep alone says so in a note.
  const auto alone = tools::deep_validate(forged);
  EXPECT_TRUE(alone.ok());
}

TEST(DeepValidation, RefusesLinkGeometryThatIsNotTheUrdfs) {
  int shrunk = 0;
  const auto forged = forged_robot("thin_link", [&](formats::RobotArtifact& robot) {
    for (auto& l : robot.model.links)
      for (auto& s : l.collision)
        if (s.type == ShapeType::Box && shrunk == 0) s.size *= 0.9, ++shrunk;
  });
  ASSERT_EQ(shrunk, 1);
  expect_refused(forged, "links/collision", with_inputs());
}

TEST(DeepValidation, CliRefusesWithTheFileTheDatasetAndTheWorstSample) {
  const auto forged = forged_env("negated_field_cli", negate_field);
  const auto plain = test::run_cli({"validate", forged});
  EXPECT_EQ(plain.exit_code, 0) << plain.output;
  const auto deep = test::run_cli({"validate", "--deep", "--samples", "300", "--json", forged}, false);
  EXPECT_EQ(deep.exit_code, 1) << deep.output;
  const auto j = nlohmann::json::parse(deep.output);
  ASSERT_EQ(j.at("files").size(), 1u);
  const auto& file = j.at("files").at(0);
  EXPECT_FALSE(file.at("ok").get<bool>());
  const std::string problem = file.at("problems").at(0);
  EXPECT_NE(problem.find(forged.string()), std::string::npos) << problem;
  EXPECT_NE(problem.find("fields/sdf/values"), std::string::npos) << problem;
  bool failed_check = false;
  for (const auto& c : file.at("deep").at("checks"))
    failed_check |= !c.at("ok").get<bool>() && c.at("samples").get<int>() > 0;
  EXPECT_TRUE(failed_check);
  const auto sound_run =
      test::run_cli({"validate", "--deep", "--samples", "300", "--set", sound().robot, sound().object, sound().env});
  EXPECT_EQ(sound_run.exit_code, 0) << sound_run.output;
}

TEST(DeepValidation, CheckInputsComparesAnObjectWithItsMeshFileAndMass) {
  test::TempDir dir;
  ASSERT_EQ(test::run_cli({"make-objects", "--out", dir.path()}).exit_code, 0);
  const fs::path object = dir / "eraser.h5";
  const auto bake = test::run_cli({"bake-object", dir / "eraser.stl", "--mass", "0.1", "--out", object});
  ASSERT_EQ(bake.exit_code, 0) << bake.output;
  const auto sound_report = tools::deep_validate(object, with_inputs());
  EXPECT_TRUE(sound_report.ok()) << (sound_report.problems().empty() ? "" : sound_report.problems().front());
  bool compared = false;
  for (const auto& c : sound_report.checks) compared |= c.dataset == "mesh/vertices" && c.samples > 0;
  EXPECT_TRUE(compared) << "the mesh file was found beside the artifact's recorded input";

  // Twice the mass (and inertia, so the mesh integrals still agree): only the inputs say it is wrong.
  auto heavy = formats::read_object_unchecked(object);
  heavy.mass.mass *= 2;
  heavy.mass.inertia *= 2;
  const fs::path forged = dir / "heavy.h5";
  formats::save_object(std::move(heavy), forged);
  EXPECT_TRUE(tools::deep_validate(forged).ok());
  expect_refused(forged, "mass/volume_mass", with_inputs());
}
