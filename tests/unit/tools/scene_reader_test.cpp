// Planning-scene YAML, URDF scenes, mesh scenes and load_scene dispatch, on hand-written files.
#include "dmgplace/tools/io/scene_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numbers>
#include <random>
#include <sstream>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

namespace fs = std::filesystem;
using test::TempDir;
using test::write_text;
using ::testing::HasSubstr;

const char* kCubeObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
    "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n";

using ::dmgplace::test::error_of;

const SceneObject& object(const Scene& s, const std::string& name) {
  for (const auto& o : s.objects)
    if (o.name == name) return o;
  throw std::runtime_error("no object " + name);
}

const double kHalf = std::sqrt(0.5);  // quaternion component of a 90 degree turn

TEST(PlanningSceneYaml, ReadsPrimitivesWithPosesAndFrames) {
  TempDir dir;
  write_text(dir / "scene.yaml", R"(
name: test
robot_state: {joint_state: {name: [a], position: [0]}}
fixed_frame_transforms:
  - child_frame_id: table_frame
    transform: {translation: [0, 0, 1], rotation: [0, 0, 0, 1]}
world:
  collision_objects:
    - id: crate
      header: {frame_id: world}
      primitives:
        - type: box
          dimensions: [0.4, 0.2, 0.1]
      primitive_poses:
        - position: [1, 2, 3]
          orientation: [0, 0, 0.7071067811865476, 0.7071067811865476]
    - id: can
      header: {frame_id: table_frame}
      pose: {position: [0.5, 0, 0], orientation: [0, 0, 0.7071067811865476, 0.7071067811865476]}
      primitives:
        - {type: cylinder, dimensions: [0.12, 0.03]}
        - {type: sphere, dimensions: [0.05]}
      primitive_poses:
        - {position: [0.1, 0, 0], orientation: [0, 0, 0, 1]}
        - position: {x: 0, y: 0, z: 0.2}
          orientation: {x: 0, y: 0, z: 0, w: 1}
    - id: shelf
      primitives:
        - type: BOX
          dimensions: [1, 1, 1]
      primitive_poses:
        - position: [0, 0, 0]
          orientation: [0, 0, 0, 0]
)");
  const Scene s = read_planning_scene_yaml(dir / "scene.yaml");
  ASSERT_EQ(s.objects.size(), 3u);
  EXPECT_EQ(s.points.rows(), 0);

  const SceneObject& crate = object(s, "crate");
  ASSERT_EQ(crate.shapes.size(), 1u);
  EXPECT_EQ(crate.shapes[0].type, ShapeType::Box);
  EXPECT_TRUE(crate.shapes[0].size.isApprox(Eigen::Vector3d(0.4, 0.2, 0.1)));  // full extents
  EXPECT_TRUE(crate.shapes[0].origin.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE((crate.shapes[0].origin.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-9));

  // can: table_frame (z + 1) * object pose (x + 0.5, turned 90 deg about z) * shape pose.
  const SceneObject& can = object(s, "can");
  ASSERT_EQ(can.shapes.size(), 2u);
  EXPECT_EQ(can.shapes[0].type, ShapeType::Cylinder);
  EXPECT_TRUE(can.shapes[0].size.isApprox(Eigen::Vector3d(0.03, 0.12, 0)));  // (radius, length, 0)
  EXPECT_TRUE(can.shapes[0].origin.translation().isApprox(Eigen::Vector3d(0.5, 0.1, 1.0), 1e-9))
      << can.shapes[0].origin.translation().transpose();
  EXPECT_EQ(can.shapes[1].type, ShapeType::Sphere);
  EXPECT_TRUE(can.shapes[1].size.isApprox(Eigen::Vector3d(0.05, 0, 0)));
  EXPECT_TRUE(can.shapes[1].origin.translation().isApprox(Eigen::Vector3d(0.5, 0, 1.2), 1e-9));
  EXPECT_TRUE((can.shapes[1].origin.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-9));

  // An all-zero quaternion is MoveIt's "unset": identity.
  EXPECT_TRUE(object(s, "shelf").shapes[0].origin.linear().isIdentity());
}

TEST(PlanningSceneYaml, PosesComposeLikeTransforms) {
  // Property: for random object and shape poses the world pose is their product.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  TempDir dir;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = Eigen::Isometry3d::Identity();
    const Eigen::Quaterniond qa = Eigen::Quaterniond::UnitRandom(), qb = Eigen::Quaterniond::UnitRandom();
    a.linear() = qa.toRotationMatrix();
    b.linear() = qb.toRotationMatrix();
    a.translation() << u(rng), u(rng), u(rng);
    b.translation() << u(rng), u(rng), u(rng);
    auto pose = [](const Eigen::Isometry3d& t, const Eigen::Quaterniond& q) {
      std::ostringstream o;
      o.precision(17);
      o << "{position: [" << t.translation().x() << ", " << t.translation().y() << ", " << t.translation().z()
        << "], orientation: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]}";
      return o.str();
    };
    write_text(dir / "p.yaml",
               "world:\n  collision_objects:\n    - id: o\n      pose: " + pose(a, qa) +
                   "\n      primitives: [{type: box, dimensions: [1, 2, 3]}]\n      primitive_poses: [" + pose(b, qb) +
                   "]\n");
    const Scene s = read_planning_scene_yaml(dir / "p.yaml");
    EXPECT_TRUE(s.objects[0].shapes[0].origin.isApprox(a * b, 1e-9)) << "trial " << trial;
  }
}

TEST(PlanningSceneYaml, ReadsMeshesFromFilesAndInline) {
  TempDir dir;
  fs::create_directories(dir / "meshes");
  write_text(dir / "meshes" / "cube.obj", kCubeObj);
  write_text(dir / "scene.yaml", R"(
world:
  collision_objects:
    - id: part
      meshes:
        - resource: meshes/cube.obj
        - vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
          triangles: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
        - vertices: [{x: 0, y: 0, z: 0}, {x: 1, y: 0, z: 0}, {x: 0, y: 1, z: 0}, {x: 0, y: 0, z: 1}]
          triangles: [{vertex_indices: [0, 2, 1]}, {vertex_indices: [0, 1, 3]}, {vertex_indices: [0, 3, 2]}, {vertex_indices: [1, 2, 3]}]
      mesh_poses:
        - {position: [0, 0, 1], orientation: [0, 0, 0, 1]}
        - {position: [2, 0, 0], orientation: [0, 0, 0, 1]}
        - {position: [3, 0, 0], orientation: [0, 0, 0, 1]}
)");
  const Scene s = read_planning_scene_yaml(dir / "scene.yaml");
  const SceneObject& part = object(s, "part");
  ASSERT_EQ(part.shapes.size(), 3u);
  for (const auto& sh : part.shapes) EXPECT_EQ(sh.type, ShapeType::Mesh);
  EXPECT_EQ(part.shapes[0].mesh.triangles.rows(), 12);
  EXPECT_TRUE(part.shapes[0].origin.translation().isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_EQ(part.shapes[1].mesh.triangles.rows(), 4);
  EXPECT_EQ(part.shapes[2].mesh.triangles.rows(), 4);
  EXPECT_TRUE(part.shapes[2].origin.translation().isApprox(Eigen::Vector3d(3, 0, 0)));
}

TEST(PlanningSceneYaml, EmptyWorldIsAnEmptyScene) {
  TempDir dir;
  write_text(dir / "e.yaml", "world: {}\n");
  EXPECT_TRUE(read_planning_scene_yaml(dir / "e.yaml").objects.empty());
}

TEST(PlanningSceneYaml, MalformedEntriesNameObjectAndField) {
  TempDir dir;
  const std::string head = "world:\n  collision_objects:\n";
  auto box = [](const std::string& id, const std::string& body) { return "    - id: " + id + "\n" + body; };
  const std::string ok_poses = "      primitive_poses: [{position: [0, 0, 0], orientation: [0, 0, 0, 1]}]\n";
  struct Bad {
    std::string yaml, expect1, expect2;
  } bad[] = {
      {box("a", "      primitives: [{type: box, dimensions: [1, 2]}]\n" + ok_poses), "object 'a'", "dimensions"},
      {box("b", "      primitives: [{type: box, dimensions: [1, -2, 3]}]\n" + ok_poses), "object 'b'", "positive"},
      {box("c", "      primitives: [{type: cylinder, dimensions: [1]}]\n" + ok_poses), "object 'c'",
       "[height, radius]"},
      {box("d", "      primitives: [{type: cone, dimensions: [1, 2]}]\n" + ok_poses), "object 'd'", "type"},
      {box("e", "      primitives: [{type: sphere, dimensions: [abc]}]\n" + ok_poses), "object 'e'", "number"},
      {box("f", "      primitives: [{type: sphere, dimensions: [1]}]\n"), "object 'f'", "primitive_poses"},
      {box("g", "      primitives: [{type: sphere, dimensions: [1]}, {type: sphere, dimensions: [1]}]\n" + ok_poses),
       "object 'g'", "primitive_poses"},
      {box("h",
           "      primitives: [{type: sphere, dimensions: [1]}]\n"
           "      primitive_poses: [{position: [0, 0], orientation: [0, 0, 0, 1]}]\n"),
       "object 'h'", "position"},
      {box("i",
           "      primitives: [{type: sphere, dimensions: [1]}]\n"
           "      primitive_poses: [{position: [0, 0, 0], orientation: [0, 0, 0, 2]}]\n"),
       "object 'i'", "orientation"},
      {box("j",
           "      primitives: [{type: sphere, dimensions: [1]}]\n"
           "      primitive_poses: [{position: [0, 0, .nan], orientation: [0, 0, 0, 1]}]\n"),
       "object 'j'", "finite"},
      {box("k", "      primitives: [{dimensions: [1]}]\n" + ok_poses), "object 'k'", "type"},
      {box("l", ""), "object 'l'", "no primitives or meshes"},
      {box("m", "      pose: [1, 2, 3]\n      primitives: [{type: sphere, dimensions: [1]}]\n" + ok_poses),
       "object 'm'", "pose"},
      {box("n", "      meshes: [{resource: missing.stl}]\n      mesh_poses: [{position: [0, 0, 0]}]\n"), "object 'n'",
       "missing.stl"},
      {box("o",
           "      meshes: [{vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles: [[0, 1, 5]]}]\n"
           "      mesh_poses: [{position: [0, 0, 0]}]\n"),
       "object 'o'", "out of range"},
      {box("p",
           "      meshes: [{vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles: [[0, 1.5, 2]]}]\n"
           "      mesh_poses: [{position: [0, 0, 0]}]\n"),
       "object 'p'", "integer"},
      {box("q", "      meshes: [{scale: 2}]\n      mesh_poses: [{position: [0, 0, 0]}]\n"), "object 'q'", "resource"},
      {box("t", "      meshes: [{triangles: [[0, 1, 2]]}]\n      mesh_poses: [{position: [0, 0, 0]}]\n"), "object 't'",
       "vertices"},
      {box("u",
           "      meshes: [{vertices: [[0, 0, 0]], triangles: [{indices: [0, 0, 0]}]}]\n"
           "      mesh_poses: [{position: [0, 0, 0]}]\n"),
       "object 'u'", "three vertex indices"},
      {box("r", "      operation: remove\n      primitives: [{type: sphere, dimensions: [1]}]\n" + ok_poses),
       "object 'r'", "operation"},
      {box("s", "      primitives: [{type: sphere, dimensions: [1]}]\n" + ok_poses) +
           box("s", "      primitives: [{type: sphere, dimensions: [1]}]\n" + ok_poses),
       "object 's'", "duplicate"},
      {"    - primitives: [{type: sphere, dimensions: [1]}]\n" + ok_poses, "collision_objects[0]", "id"},
      {"    - just a string\n", "collision_objects[0]", "map"},
  };
  for (const auto& b : bad) {
    write_text(dir / "bad.yaml", head + b.yaml);
    const std::string e = error_of([&] { read_planning_scene_yaml(dir / "bad.yaml"); });
    EXPECT_THAT(e, HasSubstr("bad.yaml")) << b.yaml;
    EXPECT_THAT(e, HasSubstr(b.expect1)) << b.yaml;
    EXPECT_THAT(e, HasSubstr(b.expect2)) << b.yaml;
  }
  for (const std::string& text :
       {std::string("world: [1, 2]\n"), std::string("robot_state: {}\n"), std::string("- a\n- b\n"),
        std::string("world: {collision_objects: {a: 1}}\n"), std::string("world:\n  collision_objects: [\n"),
        std::string("fixed_frame_transforms: [{transform: {}}]\nworld: {}\n"), std::string(""),
        std::string("\x01\x02\xff\xfe garbage: [")}) {
    write_text(dir / "bad.yaml", text);
    EXPECT_THAT(error_of([&] { read_planning_scene_yaml(dir / "bad.yaml"); }), HasSubstr("bad.yaml")) << text;
  }
  EXPECT_THAT(error_of([&] { read_planning_scene_yaml(dir / "none.yaml"); }), HasSubstr("none.yaml: file not found"));
}

// A fixed "room" URDF: root -> table (box) -> lamp (sphere, on a revolute joint at 0) -> shade.
std::string room(const std::string& lamp_limits) {
  return R"(<robot name="room">
  <link name="root"/>
  <link name="table"><collision><origin xyz="0 0 0.4"/><geometry><box size="1 2 0.05"/></geometry></collision></link>
  <link name="lamp"><collision><geometry><sphere radius="0.1"/></geometry></collision>
                    <collision><origin xyz="0 0 0.3"/><geometry><cylinder radius="0.01" length="0.6"/></geometry></collision></link>
  <joint name="table_joint" type="fixed"><parent link="root"/><child link="table"/><origin xyz="2 0 0" rpy="0 0 1.5707963267948966"/></joint>
  <joint name="lamp_joint" type="revolute"><parent link="table"/><child link="lamp"/><origin xyz="0.5 0 0.45"/>
    <axis xyz="0 0 1"/>)" +
         lamp_limits + R"(</joint>
</robot>)";
}

TEST(UrdfScene, PlacesLinksByFixedJoints) {
  TempDir dir;
  write_text(dir / "room.urdf", room(R"(<limit lower="-1" upper="1" velocity="1" effort="1"/>)"));
  const Scene s = read_urdf_scene(dir / "room.urdf");
  ASSERT_EQ(s.objects.size(), 2u);  // root has no collision geometry
  const SceneObject& table = object(s, "table");
  ASSERT_EQ(table.shapes.size(), 1u);
  EXPECT_TRUE(table.shapes[0].origin.translation().isApprox(Eigen::Vector3d(2, 0, 0.4)));
  EXPECT_TRUE(table.shapes[0].size.isApprox(Eigen::Vector3d(1, 2, 0.05)));
  const SceneObject& lamp = object(s, "lamp");
  ASSERT_EQ(lamp.shapes.size(), 2u);
  // The table frame is turned 90 degrees: its x is the world's y.
  EXPECT_TRUE(lamp.shapes[0].origin.translation().isApprox(Eigen::Vector3d(2, 0.5, 0.45), 1e-9))
      << lamp.shapes[0].origin.translation().transpose();
  EXPECT_TRUE(lamp.shapes[1].origin.translation().isApprox(Eigen::Vector3d(2, 0.5, 0.75), 1e-9));
  EXPECT_EQ(lamp.shapes[1].type, ShapeType::Cylinder);

  write_text(dir / "room.urdf", room(R"(<limit lower="0.5" upper="1" velocity="1" effort="1"/>)"));
  const std::string e = error_of([&] { read_urdf_scene(dir / "room.urdf"); });
  EXPECT_THAT(e, HasSubstr("room.urdf"));
  EXPECT_THAT(e, HasSubstr("joint 'lamp_joint'"));
}

TEST(MeshScene, OneObjectNamedAfterTheFile) {
  TempDir dir;
  write_text(dir / "crate.obj", kCubeObj);
  MeshReadOptions opt;
  opt.scale = 0.25;
  const Scene s = read_mesh_scene(dir / "crate.obj", opt);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].name, "crate");
  ASSERT_EQ(s.objects[0].shapes.size(), 1u);
  EXPECT_EQ(s.objects[0].shapes[0].type, ShapeType::Mesh);
  EXPECT_NEAR(s.objects[0].shapes[0].mesh.vertices.maxCoeff(), 0.25, 1e-12);
}

TEST(SceneLoader, DispatchesOnExtension) {
  TempDir dir;
  write_text(dir / "a.YAML",
             "world:\n  collision_objects:\n    - id: x\n      primitives: [{type: sphere, dimensions: [1]}]\n"
             "      primitive_poses: [{position: [0, 0, 0], orientation: [0, 0, 0, 1]}]\n");
  write_text(dir / "b.urdf", room(R"(<limit lower="-1" upper="1" velocity="1" effort="1"/>)"));
  write_text(dir / "c.obj", kCubeObj);
  write_text(dir / "d.pcd",
             "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
             "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n");
  EXPECT_EQ(load_scene(dir / "a.YAML").objects.at(0).name, "x");
  EXPECT_EQ(load_scene(dir / "b.urdf").objects.size(), 2u);
  EXPECT_EQ(load_scene(dir / "c.obj").objects.at(0).name, "c");
  SceneLoadOptions opt;
  opt.frame.translation() << 0, 0, 10;
  const Scene scan = load_scene(dir / "d.pcd", opt);
  ASSERT_EQ(scan.points.rows(), 2);
  EXPECT_TRUE(scan.points.row(1).isApprox(Eigen::RowVector3d(4, 5, 16)));
  // The frame moves every kind of scene, not only scans: each shape's pose is composed with it.
  opt.frame = Eigen::Translation3d(0.2, 0.4, -0.7) * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ());
  for (const char* file : {"a.YAML", "b.urdf", "c.obj"}) {
    const Scene plain = load_scene(dir / file), moved = load_scene(dir / file, opt);
    ASSERT_EQ(plain.objects.size(), moved.objects.size()) << file;
    for (std::size_t i = 0; i < plain.objects.size(); ++i)
      for (std::size_t k = 0; k < plain.objects[i].shapes.size(); ++k)
        EXPECT_TRUE((opt.frame * plain.objects[i].shapes[k].origin).isApprox(moved.objects[i].shapes[k].origin))
            << file;
  }
  opt.frame = Eigen::Isometry3d::Identity();
  // package:// in a YAML scene goes through the same package paths as URDFs.
  fs::create_directories(dir / "pkgs" / "props");
  write_text(dir / "pkgs" / "props" / "box.obj", kCubeObj);
  write_text(dir / "f.yml",
             "world:\n  collision_objects:\n    - id: prop\n      meshes: [{resource: \"package://props/box.obj\"}]\n"
             "      mesh_poses: [{position: [0, 0, 0], orientation: [0, 0, 0, 1]}]\n");
  EXPECT_THAT(error_of([&] { load_scene(dir / "f.yml"); }), HasSubstr("package://props/box.obj"));
  opt.urdf.package_paths = {dir / "pkgs"};
  EXPECT_EQ(load_scene(dir / "f.yml", opt).objects.at(0).shapes.at(0).mesh.triangles.rows(), 12);
  write_text(dir / "e.txt", "hello");
  const std::string e = error_of([&] { load_scene(dir / "e.txt", opt); });
  EXPECT_THAT(e, HasSubstr("e.txt"));
  EXPECT_THAT(e, HasSubstr("unknown scene file type"));
  EXPECT_THAT(error_of([&] { load_scene(dir / "noext"); }), HasSubstr("noext"));
}

}  // namespace
}  // namespace dmgplace::tools
