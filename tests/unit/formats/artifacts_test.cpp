#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_writer.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "artifact_mutation.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::formats;

namespace {
TriMesh unit_cube() {
  TriMesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.vertices.row(i) << (i & 1), (i >> 1 & 1), (i >> 2 & 1);
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3,
      7, 5;
  return m;
}

ObjectArtifact sample_object() {
  ObjectArtifact a;
  a.mesh = unit_cube();
  a.mass.volume = 1;
  a.mass.mass = 1000;
  a.mass.com = Eigen::Vector3d(0.5, 0.5, 0.5);
  a.mass.inertia = Eigen::Matrix3d::Identity() * 1000.0 / 6.0;
  a.header.parameters_json = R"({"scale":1})";
  a.header.inputs = {{"cube.stl", std::string(64, 'c')}};
  return a;
}

RobotArtifact sample_robot() {
  RobotArtifact a;
  RobotModel& m = a.model;
  m.name = "two_link";
  for (auto n : {"base", "upper", "tip"}) m.links.push_back({n, {}});
  Shape box;
  box.type = ShapeType::Box;
  box.size = Eigen::Vector3d(0.1, 0.1, 0.3);
  box.origin.translation() = Eigen::Vector3d(0, 0, 0.15);
  m.links[1].collision.push_back(box);
  Shape mesh;
  mesh.type = ShapeType::Mesh;
  mesh.size = Eigen::Vector3d::Ones();
  mesh.mesh = unit_cube();
  mesh.hull = mesh.mesh.triangles;  // a cube is its own hull
  m.links[2].collision.push_back(mesh);
  Joint j1;
  j1.name = "j1";
  j1.type = JointType::Revolute;
  j1.parent = 0;
  j1.child = 1;
  j1.lower = -2;
  j1.upper = 2;
  j1.velocity = 1;
  j1.acceleration = 2.5;
  j1.origin.translation() = Eigen::Vector3d(0, 0, 0.2);
  Joint j2 = j1;
  j2.name = "j2";
  j2.type = JointType::Prismatic;
  j2.parent = 1;
  j2.child = 2;
  j2.mimic = 0;
  j2.mimic_multiplier = 0.5;
  j2.axis = Eigen::Vector3d::UnitY();
  m.joints = {j1, j2};
  m.arm_base = "base";
  m.arm_tip = "tip";
  m.allowed_pairs = {{0, 1}};
  a.spheres = {{1, Eigen::Vector3d(0, 0, 0.15), 0.2}, {2, Eigen::Vector3d(0.5, 0.5, 0.5), 0.9}};
  SelfDistanceTable t;
  t.link_a = 0;
  t.link_b = 2;
  t.joints = {0, -1};
  t.lower = {-2, 0};
  t.step = {1, 1};
  t.slope = {0.7, 0};
  t.count = {5, 1};
  t.distance = {0.1f, 0.05f, 0.0f, 0.05f, 0.1f};
  a.self_tables = {t};
  return a;
}

EnvironmentArtifact sample_env() {
  EnvironmentArtifact a;
  a.volume = Eigen::AlignedBox3d(Eigen::Vector3d(0, -0.5, 0), Eigen::Vector3d(1, 0.5, 1));
  SceneObject table{"table", {}};
  Shape top;
  top.type = ShapeType::Box;
  top.size = Eigen::Vector3d(1, 1, 0.05);
  top.origin.translation() = Eigen::Vector3d(0.6, 0, 0.4);
  top.origin.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  table.shapes.push_back(top);
  SceneObject can{"can", {}};
  Shape cyl;
  cyl.type = ShapeType::Cylinder;
  cyl.size = Eigen::Vector3d(0.03, 0.12, 0);
  can.shapes.push_back(cyl);
  a.scene.objects = {table, can};
  a.scene.points.resize(2, 3);
  a.scene.points << 1, 2, 3, 4, 5, 6;
  return a;
}
}  // namespace

TEST(ObjectArtifact, RoundTripIsExactAndValid) {
  test::TempDir dir;
  save_object(sample_object(), dir / "o.h5");
  auto a = load_object(dir / "o.h5");
  EXPECT_EQ(a.header.schema, kObjectSchema);
  EXPECT_EQ(a.mesh.vertices, unit_cube().vertices);
  EXPECT_EQ(a.mesh.triangles, unit_cube().triangles);
  EXPECT_EQ(a.mass.com, Eigen::Vector3d(0.5, 0.5, 0.5));
  EXPECT_DOUBLE_EQ(a.mass.mass, 1000);
  EXPECT_EQ(a.header.inputs.at(0).path, "cube.stl");
  EXPECT_TRUE(check_object(a).empty());
  EXPECT_TRUE(validate_artifact(dir / "o.h5").empty());
}

TEST(ObjectArtifact, InvariantViolationsAreReported) {
  auto a = sample_object();
  a.mesh.triangles(3, 1) = 99;
  a.mass.com = Eigen::Vector3d(5, 5, 5);
  a.mass.volume = -1;
  auto p = check_object(a);
  ASSERT_GE(p.size(), 2u);
  EXPECT_NE(p[0].find("index out of range"), std::string::npos);
  auto b = sample_object();
  b.mass.com = Eigen::Vector3d(5, 5, 5);
  ASSERT_EQ(check_object(b).size(), 1u);
  EXPECT_NE(check_object(b)[0].find("com"), std::string::npos);
  auto c = sample_object();
  c.mesh.vertices(0, 0) = NAN;
  EXPECT_FALSE(check_object(c).empty());
}

TEST(RobotArtifact, RoundTripKeepsTreeShapesAndPairs) {
  test::TempDir dir;
  save_robot(sample_robot(), dir / "r.h5");
  auto r = load_robot(dir / "r.h5");
  const auto& m = r.model;
  ASSERT_EQ(m.links.size(), 3u);
  ASSERT_EQ(m.joints.size(), 2u);
  EXPECT_EQ(m.joints[1].type, JointType::Prismatic);
  EXPECT_EQ(m.joints[1].mimic, 0);
  EXPECT_DOUBLE_EQ(m.joints[1].mimic_multiplier, 0.5);
  EXPECT_DOUBLE_EQ(m.joints[0].velocity, 1);
  EXPECT_DOUBLE_EQ(m.joints[0].acceleration, 2.5);
  EXPECT_TRUE(m.joints[0].origin.isApprox(sample_robot().model.joints[0].origin));
  EXPECT_EQ(m.links[2].collision.at(0).mesh.triangles, unit_cube().triangles);
  EXPECT_EQ(m.links[2].collision.at(0).hull, unit_cube().triangles);
  EXPECT_EQ(m.links[1].collision.at(0).size, Eigen::Vector3d(0.1, 0.1, 0.3));
  EXPECT_EQ(m.allowed_pairs, (std::vector<std::pair<int, int>>{{0, 1}}));
  EXPECT_EQ(m.arm_tip, "tip");
  ASSERT_EQ(r.spheres.size(), 2u);
  EXPECT_EQ(r.spheres[1].link, 2);
  EXPECT_DOUBLE_EQ(r.spheres[1].radius, 0.9);
  ASSERT_EQ(r.self_tables.size(), 1u);
  EXPECT_EQ(r.self_tables[0].distance, sample_robot().self_tables[0].distance);
  EXPECT_EQ(r.self_tables[0].count, (std::array<int, 2>{5, 1}));
  // Nearest node (q = -0.9 -> node 1 at -1: 0.05) minus slope * 0.1.
  EXPECT_NEAR(r.self_tables[0].lower_bound(-0.9, 0), 0.05 - 0.07, 1e-7);
  EXPECT_TRUE(check_robot(r).empty());
  EXPECT_TRUE(validate_artifact(dir / "r.h5").empty());
}

TEST(RobotArtifact, BrokenTreesAndLimitsAreReported) {
  auto loop = sample_robot();
  loop.model.joints[0].parent = 2;  // base <- tip: a loop and no root
  EXPECT_FALSE(check_robot(loop).empty());
  auto limits = sample_robot();
  std::swap(limits.model.joints[0].lower, limits.model.joints[0].upper);
  auto p = check_robot(limits);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].find("limits"), std::string::npos);
  auto chain = sample_robot();
  chain.model.arm_base = "tip";
  chain.model.arm_tip = "base";
  p = check_robot(chain);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].find("does not descend"), std::string::npos);
  auto uncovered = sample_robot();
  uncovered.spheres.pop_back();
  p = check_robot(uncovered);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].find("'tip' has collision geometry but no spheres"), std::string::npos);
  auto pair = sample_robot();
  pair.model.allowed_pairs.push_back({1, 1});
  EXPECT_EQ(check_robot(pair).size(), 1u);
  auto table = sample_robot();
  table.self_tables[0].distance[2] = std::nanf("");
  p = check_robot(table);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].find("self_tables[0]: distance negative or not finite"), std::string::npos);
  table = sample_robot();
  table.self_tables[0].distance.pop_back();
  p = check_robot(table);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].find("does not match the grid"), std::string::npos);
  table = sample_robot();
  table.self_tables[0].joints = {5, -1};
  EXPECT_EQ(check_robot(table).size(), 1u);
  table = sample_robot();
  table.self_tables[0].slope[0] = -1;
  EXPECT_EQ(check_robot(table).size(), 1u);
}

// A file whose tables declare more nodes than it holds is reported at load, naming the dataset.
TEST(RobotArtifact, TableCountsThatDisagreeWithTheDataAreCorrupt) {
  test::TempDir dir;
  auto r = sample_robot();
  r.self_tables[0].count = {6, 1};  // 6 declared, 5 stored
  r.self_tables[0].distance.push_back(0);
  save_robot(r, dir / "r.h5");
  r = load_robot(dir / "r.h5");
  EXPECT_EQ(r.self_tables[0].distance.size(), 6u);
  auto bad = sample_robot();
  bad.self_tables.push_back(bad.self_tables[0]);
  bad.self_tables[1].count = {1000, 1};
  EXPECT_THROW(
      {
        try {
          save_robot(bad, dir / "bad.h5");
          load_robot(dir / "bad.h5");
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("fewer nodes than the tables declare"), std::string::npos) << e.what();
          throw;
        }
      },
      Error);
}

TEST(EnvironmentArtifact, RoundTripKeepsWorldPosesAndPoints) {
  test::TempDir dir;
  save_environment(sample_env(), dir / "e.h5");
  auto e = load_environment(dir / "e.h5");
  ASSERT_EQ(e.scene.objects.size(), 2u);
  EXPECT_EQ(e.scene.objects[1].name, "can");
  EXPECT_TRUE(e.scene.objects[0].shapes.at(0).origin.isApprox(sample_env().scene.objects[0].shapes[0].origin, 1e-12));
  EXPECT_EQ(e.scene.points, sample_env().scene.points);
  EXPECT_TRUE(e.volume.isApprox(sample_env().volume));
  EXPECT_TRUE(check_environment(e).empty());
  auto bad = sample_env();
  bad.volume = Eigen::AlignedBox3d(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 1));
  bad.scene.objects[1].shapes[0].size.x() = 0;
  EXPECT_EQ(check_environment(bad).size(), 2u);
}

TEST(ValidateArtifact, WrongVersionUnknownKindAndCorruptionAreReported) {
  test::TempDir dir;
  {
    ArtifactHeader h;
    h.schema = kObjectSchema;
    h.schema_version = 99;
    H5Writer w(dir / "future.h5", h);
    w.commit();
  }
  auto p = validate_artifact(dir / "future.h5");
  ASSERT_FALSE(p.empty());
  EXPECT_NE(p[0].find("schema_version"), std::string::npos);
  EXPECT_NE(p[0].find("future.h5"), std::string::npos);
  {
    ArtifactHeader h;
    h.schema = "something.else";
    h.schema_version = 1;
    H5Writer w(dir / "other.h5", h);
    w.commit();
  }
  p = validate_artifact(dir / "other.h5");
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].find("unknown artifact kind"), std::string::npos);

  // Flip a byte inside the mesh data: validate must say which dataset is corrupt.
  auto obj = sample_object();
  obj.mesh.vertices = RowMatrixX3d::Random(4000, 3);
  obj.mesh.triangles.resize(1, 3);
  obj.mesh.triangles << 0, 1, 2;
  obj.mass.com = Eigen::Vector3d::Zero();
  save_object(obj, dir / "o.h5");
  std::string bytes = test::read_text(dir / "o.h5");
  bytes[bytes.size() / 2] ^= 0x10;
  test::write_text(dir / "o.h5", bytes);
  p = validate_artifact(dir / "o.h5");
  ASSERT_FALSE(p.empty());
  EXPECT_NE(p[0].find("o.h5"), std::string::npos);
}

// ---- The loaders' semantic gate (issue 19): what `validate` rejects, no loader accepts. ----
namespace {

bool verify_checksums_ok(const std::filesystem::path& p) { return H5Reader(p).verify_all_checksums().empty(); }

// Saves `a` (save_* does not check), then expects load to refuse it naming the file and `what`,
// the unchecked reader to read it, and validate to report it.
template <class Artifact, class Save, class Load, class Read>
void expect_refused(const Artifact& a, Save save, Load load, Read read, const std::string& what) {
  test::TempDir dir;
  const auto path = dir / "crafted.h5";
  save(a, path);
  try {
    load(path);
    ADD_FAILURE() << "loaded an artifact with: " << what;
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path.string()), std::string::npos) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
  }
  EXPECT_NO_THROW(read(path));
  const auto problems = validate_artifact(path);
  ASSERT_FALSE(problems.empty()) << what;
  bool named = false;
  for (const auto& p : problems) named |= p.find(what) != std::string::npos;
  EXPECT_TRUE(named) << problems.front();
}

void expect_object_refused(const ObjectArtifact& a, const std::string& what) {
  expect_refused(a, save_object, load_object, read_object_unchecked, what);
}
void expect_robot_refused(const RobotArtifact& a, const std::string& what) {
  expect_refused(a, save_robot, load_robot, read_robot_unchecked, what);
}
void expect_env_refused(const EnvironmentArtifact& a, const std::string& what) {
  expect_refused(a, save_environment, load_environment, read_environment_unchecked, what);
}

// The cube resting on its z = 0 face.
PlacementFace cube_bottom() {
  PlacementFace f;
  f.normal = Eigen::Vector3d(0, 0, -1);
  f.polygon = {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
  f.rotation = Eigen::Quaterniond::Identity();
  f.margin = 0.5;
  f.height = 0;
  return f;
}

}  // namespace

TEST(LoadGate, SoundArtifactsLoad) {
  auto o = sample_object();
  o.placement.faces = {cube_bottom()};
  ASSERT_TRUE(check_object(o).empty()) << check_object(o).front();
  test::TempDir dir;
  save_object(o, dir / "o.h5");
  EXPECT_EQ(load_object(dir / "o.h5").header.source_file, (dir / "o.h5").string());
}

TEST(LoadGate, ObjectsThatValidateRejectsAreNotLoaded) {
  auto nan_margin = sample_object();
  nan_margin.placement.faces = {cube_bottom()};
  nan_margin.placement.faces[0].margin = std::nan("");
  expect_object_refused(nan_margin, "margin or height not finite");
  auto nan_height = sample_object();
  nan_height.placement.faces = {cube_bottom()};
  nan_height.placement.faces[0].height = std::nan("");
  expect_object_refused(nan_height, "margin or height not finite");
  auto nan_rotation = sample_object();
  nan_rotation.placement.faces = {cube_bottom()};
  nan_rotation.placement.faces[0].rotation.coeffs().setConstant(std::nan(""));
  expect_object_refused(nan_rotation, "rotation does not turn the normal");
  auto zero_step = sample_object();
  zero_step.dmg.angle_step_deg = 0;  // SIGFPE in the runtime before the gate
  expect_object_refused(zero_step, "angle step");
  auto tiny_step = sample_object();
  tiny_step.dmg.angle_step_deg = 360.0 / 36000000;  // 36 million angles per node: gigabytes
  expect_object_refused(tiny_step, "angle step");
  auto edge = sample_object();
  edge.dmg.edges = {{0, 7}, {7, 0}};  // no such nodes: SIGSEGV in the runtime before the gate
  expect_object_refused(edge, "dmg/edges");
  auto gripper = sample_object();
  gripper.dmg.gripper.tip_offset = std::nan("");
  expect_object_refused(gripper, "dmg/gripper");
  auto mass = sample_object();
  mass.mass.mass = -1;
  expect_object_refused(mass, "mass/mass");
}

TEST(LoadGate, RobotsThatValidateRejectsAreNotLoaded) {
  auto loop = sample_robot();
  loop.model.joints[0].mimic = 1;  // j1 <- j2 <- j1: FK recursed forever before the gate
  loop.model.joints[0].mimic_multiplier = 1;
  expect_robot_refused(loop, "mimic loop");
  auto axis = sample_robot();
  axis.model.joints[0].axis = Eigen::Vector3d(std::nan(""), 0, 1);
  expect_robot_refused(axis, "axis is not a finite unit vector");
  auto velocity = sample_robot();
  velocity.model.joints[0].velocity = std::nan("");
  expect_robot_refused(velocity, "velocity limit");
  auto acceleration = sample_robot();
  acceleration.model.joints[0].acceleration = -1;
  expect_robot_refused(acceleration, "acceleration limit");
  auto multiplier = sample_robot();
  multiplier.model.joints[1].mimic_multiplier = std::nan("");
  expect_robot_refused(multiplier, "mimic multiplier");
  auto far = sample_robot();
  far.model.links[1].collision[0].size.x() = 1e9;  // a 1e9 m box: bake-robot ran out of memory on it
  expect_robot_refused(far, "beyond");
}

// The exact layer measures gaps against a link mesh's stored hull: one that leaves a vertex out,
// is open, or points a face inwards would make those gaps too large.
TEST(LoadGate, HullsThatDoNotContainTheirMeshAreRefused) {
  auto outside = sample_robot();
  TriMesh& mesh = outside.model.links[2].collision[0].mesh;
  mesh.vertices.conservativeResize(mesh.vertices.rows() + 1, 3);
  mesh.vertices.row(mesh.vertices.rows() - 1) = Eigen::RowVector3d(2, 0.5, 0.5);  // beyond the cube
  expect_robot_refused(outside, "outside convex hull face");
  auto open = sample_robot();
  RowMatrixX3i& hull = open.model.links[2].collision[0].hull;
  hull.conservativeResize(hull.rows() - 1, 3);
  expect_robot_refused(open, "not closed");
  auto inward = sample_robot();
  RowMatrixX3i& flipped = inward.model.links[2].collision[0].hull;
  for (Eigen::Index f = 0; f < flipped.rows(); ++f) std::swap(flipped(f, 1), flipped(f, 2));
  expect_robot_refused(inward, "outside convex hull face");
  auto index = sample_robot();
  index.model.links[2].collision[0].hull(0, 0) = 99;
  expect_robot_refused(index, "hull triangle index out of range");
}

TEST(LoadGate, EnvironmentsThatValidateRejectsAreNotLoaded) {
  auto far = sample_env();
  far.volume.max().x() = 1e300;
  expect_env_refused(far, "volume");
  auto huge = sample_env();
  huge.scene.objects[0].shapes[0].size.x() = 1e300;
  expect_env_refused(huge, "beyond");
}

// The zero quaternion cannot be made through the value types (they hold matrices): write it into
// the file, checksum recomputed, as a buggy writer would.
TEST(LoadGate, ZeroCollisionQuaternionIsRefused) {
  test::TempDir dir;
  save_robot(sample_robot(), dir / "r.h5");
  test::mutate_dataset(dir / "r.h5", dir / "q.h5", "links/collision/pose", 3, 0);  // shape 0: x y z qx qy qz qw
  for (std::size_t k = 4; k < 7; ++k)
    test::mutate_dataset(dir / "q.h5", dir / "q.h5.tmp", "links/collision/pose", k, 0),
        std::filesystem::rename(dir / "q.h5.tmp", dir / "q.h5");
  ASSERT_TRUE(verify_checksums_ok(dir / "q.h5"));
  try {
    load_robot(dir / "q.h5");
    ADD_FAILURE() << "loaded a zero collision quaternion";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("quaternion is not of unit length"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find((dir / "q.h5").string()), std::string::npos) << e.what();
  }
}

// Found by the structure-aware fuzzer under UBSan: a range whose first + count overflowed int64
// before the bounds check, and a 1e300 vertex whose extent made the surface index cast NaN.
TEST(LoadGate, OverflowingRangesAndHugeVerticesAreRefused) {
  test::TempDir dir;
  auto o = sample_object();
  o.placement.faces = {cube_bottom()};
  save_object(o, dir / "o.h5");
  test::mutate_dataset(dir / "o.h5", dir / "range.h5", "placement/polygon_ranges", 0, 9.3e18);  // clipped to INT64_MAX
  EXPECT_THAT(test::error_of([&] { load_object(dir / "range.h5"); }),
              ::testing::AllOf(::testing::HasSubstr("range.h5"), ::testing::HasSubstr("range out of bounds")));
  test::mutate_dataset(dir / "o.h5", dir / "range2.h5", "placement/polygon_ranges", 1, 9.3e18);
  EXPECT_THAT(test::error_of([&] { load_object(dir / "range2.h5"); }), ::testing::HasSubstr("range out of bounds"));
  test::mutate_dataset(dir / "o.h5", dir / "far.h5", "mesh/vertices", 0, 1e300);
  EXPECT_THAT(test::error_of([&] { load_object(dir / "far.h5"); }), ::testing::HasSubstr("a vertex beyond 1000 m"));
  auto r = sample_robot();
  save_robot(r, dir / "r.h5");
  test::mutate_dataset(dir / "r.h5", dir / "shape.h5", "links/collision/mesh_ranges", 5,
                       9.3e18);  // shape 1's vertex count
  EXPECT_THAT(test::error_of([&] { load_robot(dir / "shape.h5"); }), ::testing::HasSubstr("mesh range outside"));
}
