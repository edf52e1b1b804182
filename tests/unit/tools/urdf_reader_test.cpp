// read_urdf / apply_srdf / set_arm_chain on small hand-written robots.
#include "dmgplace/tools/io/urdf_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numbers>

#include "dmgplace/formats/error.hpp"
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

// A small gripper arm: base (box) -> shoulder (revolute, cylinder) -> wrist (continuous, mesh)
// -> two fingers (prismatic, one mimicking the other) and a fixed sensor (sphere).
std::string robot(const std::string& mesh_uri, const std::string& shoulder_type = "revolute",
                  const std::string& shoulder_limit = R"(<limit lower="-1.5" upper="2.5" velocity="3" effort="1"/>)",
                  const std::string& mimic = R"(<mimic joint="finger_a" multiplier="-2" offset="0.01"/>)") {
  return R"(<?xml version="1.0"?>
<robot name="gripper">
  <link name="base"><collision><origin xyz="0 0 0.05" rpy="0 0 0"/><geometry><box size="0.4 0.3 0.1"/></geometry></collision></link>
  <link name="shoulder"><collision><geometry><cylinder radius="0.05" length="0.6"/></geometry></collision></link>
  <link name="wrist"><collision><origin xyz="0.1 0 0"/><geometry><mesh filename=")" +
         mesh_uri + R"(" scale="0.1 0.2 0.3"/></geometry></collision></link>
  <link name="finger_a"/>
  <link name="finger_b"/>
  <link name="sensor"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
  <joint name="shoulder_joint" type=")" +
         shoulder_type + R"(">
    <parent link="base"/><child link="shoulder"/>
    <origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/><axis xyz="0 0 2"/>)" +
         shoulder_limit + R"(
  </joint>
  <joint name="wrist_joint" type="continuous">
    <parent link="shoulder"/><child link="wrist"/><origin xyz="0 0 0.6"/><axis xyz="1 1 0"/>
  </joint>
  <joint name="finger_a" type="prismatic">
    <parent link="wrist"/><child link="finger_a"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" velocity="0.2" effort="1"/>
  </joint>
  <joint name="finger_b" type="prismatic">
    <parent link="wrist"/><child link="finger_b"/><axis xyz="0 -1 0"/>
    <limit lower="0" upper="0.04" velocity="0.2" effort="1"/>)" +
         mimic + R"(
  </joint>
  <joint name="sensor_mount" type="fixed"><parent link="shoulder"/><child link="sensor"/><origin xyz="0 0.1 0"/></joint>
</robot>
)";
}

using ::dmgplace::test::error_of;

// <tmp>/pkgs/my_pkg/meshes/cube.obj and <tmp>/robots/arm.urdf.
struct Fixture {
  TempDir dir;
  fs::path urdf = dir / "robots" / "arm.urdf";
  fs::path pkgs = dir / "pkgs";
  Fixture() {
    fs::create_directories(pkgs / "my_pkg" / "meshes");
    fs::create_directories(urdf.parent_path());
    write_text(pkgs / "my_pkg" / "meshes" / "cube.obj", kCubeObj);
  }
  RobotModel read(const std::string& text) {
    write_text(urdf, text);
    return read_urdf(urdf, {{pkgs}});
  }
};

TEST(UrdfReader, ReadsLinksJointsShapesAndMimic) {
  Fixture fx;
  const RobotModel m = fx.read(robot("package://my_pkg/meshes/cube.obj"));
  EXPECT_EQ(m.name, "gripper");
  ASSERT_EQ(m.links.size(), 6u);
  ASSERT_EQ(m.joints.size(), 5u);
  EXPECT_TRUE(m.arm_base.empty() && m.arm_tip.empty() && m.allowed_pairs.empty());
  EXPECT_EQ(m.links[0].name, "base");  // the root comes first

  // Every joint's parent link precedes its child link, and joints come in child order.
  for (std::size_t i = 0; i < m.joints.size(); ++i) {
    EXPECT_LT(m.joints[i].parent, m.joints[i].child) << m.joints[i].name;
    if (i > 0) {
      EXPECT_LT(m.joints[i - 1].child, m.joints[i].child);
    }
  }

  const Joint& shoulder = m.joints[std::size_t(m.joint_index("shoulder_joint"))];
  EXPECT_EQ(shoulder.type, JointType::Revolute);
  EXPECT_EQ(m.links[std::size_t(shoulder.parent)].name, "base");
  EXPECT_EQ(m.links[std::size_t(shoulder.child)].name, "shoulder");
  EXPECT_TRUE(shoulder.axis.isApprox(Eigen::Vector3d::UnitZ()));  // given as 0 0 2
  EXPECT_TRUE(shoulder.origin.translation().isApprox(Eigen::Vector3d(0, 0, 0.1)));
  EXPECT_TRUE((shoulder.origin.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-9));
  EXPECT_DOUBLE_EQ(shoulder.lower, -1.5);
  EXPECT_DOUBLE_EQ(shoulder.upper, 2.5);
  EXPECT_DOUBLE_EQ(shoulder.velocity, 3.0);

  const Joint& wrist = m.joints[std::size_t(m.joint_index("wrist_joint"))];
  EXPECT_EQ(wrist.type, JointType::Continuous);
  EXPECT_NEAR(wrist.axis.norm(), 1.0, 1e-12);
  EXPECT_TRUE(wrist.axis.isApprox(Eigen::Vector3d(1, 1, 0).normalized()));
  EXPECT_DOUBLE_EQ(wrist.lower, -std::numbers::pi);
  EXPECT_DOUBLE_EQ(wrist.upper, std::numbers::pi);

  const Joint& fb = m.joints[std::size_t(m.joint_index("finger_b"))];
  EXPECT_EQ(fb.type, JointType::Prismatic);
  EXPECT_EQ(fb.mimic, m.joint_index("finger_a"));
  EXPECT_DOUBLE_EQ(fb.mimic_multiplier, -2.0);
  EXPECT_DOUBLE_EQ(fb.mimic_offset, 0.01);
  EXPECT_EQ(m.joints[std::size_t(m.joint_index("finger_a"))].mimic, -1);
  EXPECT_EQ(m.joints[std::size_t(m.joint_index("sensor_mount"))].type, JointType::Fixed);

  const auto& base = m.links[std::size_t(m.link_index("base"))].collision;
  ASSERT_EQ(base.size(), 1u);
  EXPECT_EQ(base[0].type, ShapeType::Box);
  EXPECT_TRUE(base[0].size.isApprox(Eigen::Vector3d(0.4, 0.3, 0.1)));
  EXPECT_TRUE(base[0].origin.translation().isApprox(Eigen::Vector3d(0, 0, 0.05)));
  const auto& cyl = m.links[std::size_t(m.link_index("shoulder"))].collision;
  ASSERT_EQ(cyl.size(), 1u);
  EXPECT_EQ(cyl[0].type, ShapeType::Cylinder);
  EXPECT_TRUE(cyl[0].size.isApprox(Eigen::Vector3d(0.05, 0.6, 0)));
  const auto& sph = m.links[std::size_t(m.link_index("sensor"))].collision;
  ASSERT_EQ(sph.size(), 1u);
  EXPECT_EQ(sph[0].type, ShapeType::Sphere);
  EXPECT_TRUE(sph[0].size.isApprox(Eigen::Vector3d(0.02, 0, 0)));

  const auto& mesh = m.links[std::size_t(m.link_index("wrist"))].collision;
  ASSERT_EQ(mesh.size(), 1u);
  EXPECT_EQ(mesh[0].type, ShapeType::Mesh);
  EXPECT_TRUE(mesh[0].size.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_EQ(mesh[0].mesh.triangles.rows(), 12);
  const Eigen::RowVector3d ext =
      mesh[0].mesh.vertices.colwise().maxCoeff() - mesh[0].mesh.vertices.colwise().minCoeff();
  EXPECT_TRUE(ext.isApprox(Eigen::RowVector3d(0.1, 0.2, 0.3), 1e-9)) << ext;  // URDF scale applied
  EXPECT_TRUE(mesh[0].origin.translation().isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_TRUE(m.links[std::size_t(m.link_index("finger_a"))].collision.empty());
}

TEST(UrdfReader, ResolvesEveryKindOfMeshPath) {
  Fixture fx;
  // package path P/NAME/rest
  EXPECT_NO_THROW(fx.read(robot("package://my_pkg/meshes/cube.obj")));
  // package path P/rest (P is the package itself)
  write_text(fx.urdf, robot("package://my_pkg/meshes/cube.obj"));
  EXPECT_NO_THROW(read_urdf(fx.urdf, {{fx.pkgs / "my_pkg"}}));
  // relative to the URDF's folder, and absolute / file://
  EXPECT_NO_THROW(fx.read(robot("../pkgs/my_pkg/meshes/cube.obj")));
  EXPECT_NO_THROW(fx.read(robot((fx.pkgs / "my_pkg/meshes/cube.obj").string())));
  EXPECT_NO_THROW(fx.read(robot("file://" + (fx.pkgs / "my_pkg/meshes/cube.obj").string())));
  // an ancestor folder named like the package, with no package path at all
  const fs::path inside = fx.pkgs / "my_pkg" / "urdf" / "arm.urdf";
  fs::create_directories(inside.parent_path());
  write_text(inside, robot("package://my_pkg/meshes/cube.obj"));
  EXPECT_EQ(read_urdf(inside).links.size(), 6u);
  // ... also when the URDF is named through ".." and from the current folder.
  EXPECT_EQ(read_urdf(fx.pkgs / "my_pkg" / "urdf" / ".." / "urdf" / "arm.urdf").links.size(), 6u);
  const fs::path cwd = fs::current_path();
  fs::current_path(inside.parent_path());
  EXPECT_NO_THROW(read_urdf("arm.urdf"));
  fs::current_path(cwd);
}

TEST(UrdfReader, MissingMeshNamesTheLink) {
  Fixture fx;
  for (const std::string uri : {"package://my_pkg/meshes/nope.stl", "package://other_pkg/meshes/cube.obj",
                                "meshes/nope.stl", "package://broken"}) {
    const std::string e = error_of([&] { fx.read(robot(uri)); });
    EXPECT_THAT(e, HasSubstr("arm.urdf")) << uri;
    EXPECT_THAT(e, HasSubstr("link 'wrist'")) << uri;
    EXPECT_THAT(e, HasSubstr("not found")) << uri;
  }
  // A mesh file that exists but is garbage: still names the link and the mesh file.
  write_text(fx.pkgs / "my_pkg" / "meshes" / "bad.stl", "solid nothing\nendsolid\n");
  const std::string e = error_of([&] { fx.read(robot("package://my_pkg/meshes/bad.stl")); });
  EXPECT_THAT(e, HasSubstr("link 'wrist'"));
  EXPECT_THAT(e, HasSubstr("bad.stl"));
}

TEST(UrdfReader, RejectsBadJoints) {
  Fixture fx;
  const std::string mesh = "package://my_pkg/meshes/cube.obj";
  struct Bad {
    std::string type, limit, mimic, expect;
  } bad[] = {
      {"revolute", R"(<limit lower="1" upper="-1" velocity="1" effort="1"/>)", "", "lower"},
      {"prismatic", R"(<limit lower="0.5" upper="0.1" velocity="1" effort="1"/>)", "", "above upper"},
      {"revolute", R"(<limit lower="nan" upper="1" velocity="1" effort="1"/>)", "", "arm.urdf"},
      {"revolute", R"(<limit lower="-1" upper="1" velocity="-1" effort="1"/>)", "", "velocity"},
      {"revolute", "", "", "arm.urdf"},  // revolute without <limit>
      {"floating", "", "", "floating"},
      {"planar", R"(<limit lower="-1" upper="1" velocity="1" effort="1"/>)", "", "planar"},
      {"revolute", R"(<limit lower="-1" upper="1" velocity="1" effort="1"/>)", R"(<mimic joint="ghost"/>)", "ghost"},
      {"revolute", R"(<limit lower="-1" upper="1" velocity="1" effort="1"/>)", R"(<mimic joint="finger_b"/>)",
       "itself"},
  };
  for (const auto& b : bad) {
    const std::string e = error_of([&] { fx.read(robot(mesh, b.type, b.limit, b.mimic)); });
    EXPECT_THAT(e, HasSubstr("arm.urdf")) << b.type << " " << b.limit << " " << b.mimic;
    EXPECT_THAT(e, HasSubstr(b.expect)) << b.type << " " << b.limit << " " << b.mimic;
  }
  // The joint is named in the error when we (not urdfdom) reject it.
  EXPECT_THAT(error_of([&] { fx.read(robot(mesh, "floating", "")); }), HasSubstr("joint 'shoulder_joint'"));
  EXPECT_THAT(
      error_of([&] { fx.read(robot(mesh, "revolute", R"(<limit lower="1" upper="0" velocity="1" effort="1"/>)")); }),
      HasSubstr("joint 'shoulder_joint'"));
  // A zero axis on a moving joint.
  std::string zero_axis = robot(mesh);
  zero_axis.replace(zero_axis.find(R"(<axis xyz="0 0 2"/>)"), 19, R"(<axis xyz="0 0 0"/>)");
  EXPECT_THAT(error_of([&] { fx.read(zero_axis); }), HasSubstr("axis"));
}

TEST(UrdfReader, RejectsBrokenFiles) {
  Fixture fx;
  EXPECT_THAT(error_of([&] { read_urdf(fx.dir / "nope.urdf"); }), HasSubstr("nope.urdf: file not found"));
  EXPECT_THAT(error_of([&] { fx.read("<robot name='x'><link name='a'>"); }), HasSubstr("arm.urdf"));
  EXPECT_THAT(error_of([&] { fx.read("not xml at all \x01\x02"); }), HasSubstr("arm.urdf"));
  // Two roots.
  EXPECT_THAT(error_of([&] { fx.read("<robot name='x'><link name='a'/><link name='b'/></robot>"); }),
              HasSubstr("arm.urdf"));
  // A non-positive primitive size.
  std::string neg = robot("package://my_pkg/meshes/cube.obj");
  neg.replace(neg.find(R"(radius="0.02")"), 13, R"(radius="-0.02")");
  EXPECT_THAT(error_of([&] { fx.read(neg); }), HasSubstr("link 'sensor'"));
}

TEST(Srdf, DisabledCollisionsBecomeAllowedPairs) {
  Fixture fx;
  RobotModel m = fx.read(robot("package://my_pkg/meshes/cube.obj"));
  const fs::path srdf = fx.dir / "arm.srdf";
  write_text(srdf, R"(<?xml version="1.0"?>
<robot name="gripper">
  <group name="arm"><chain base_link="base" tip_link="wrist"/></group>
  <disable_collisions link1="base" link2="shoulder" reason="Adjacent"/>
  <disable_collisions link1="wrist" link2="shoulder" reason="Adjacent"/>
  <disable_collisions link1="shoulder" link2="base" reason="Again, reversed"/>
  <disable_collisions link1="finger_a" link2="finger_b" reason="Never"/>
</robot>)");
  apply_srdf(m, srdf);
  ASSERT_EQ(m.allowed_pairs.size(), 3u);
  for (const auto& [a, b] : m.allowed_pairs) EXPECT_LT(a, b);
  auto has = [&](const char* a, const char* b) {
    const int i = m.link_index(a), j = m.link_index(b);
    const std::pair<int, int> p{std::min(i, j), std::max(i, j)};
    return std::find(m.allowed_pairs.begin(), m.allowed_pairs.end(), p) != m.allowed_pairs.end();
  };
  EXPECT_TRUE(has("base", "shoulder"));
  EXPECT_TRUE(has("wrist", "shoulder"));
  EXPECT_TRUE(has("finger_b", "finger_a"));
  EXPECT_FALSE(has("base", "wrist"));
}

TEST(Srdf, RejectsUnknownLinksAndBrokenFiles) {
  Fixture fx;
  RobotModel m = fx.read(robot("package://my_pkg/meshes/cube.obj"));
  const fs::path srdf = fx.dir / "bad.srdf";
  write_text(srdf, R"(<robot name="gripper"><disable_collisions link1="base" link2="elbow" reason="Never"/></robot>)");
  std::string e = error_of([&] { apply_srdf(m, srdf); });
  EXPECT_THAT(e, HasSubstr("bad.srdf"));
  EXPECT_THAT(e, HasSubstr("'elbow'"));
  write_text(srdf, R"(<robot name="gripper"><disable_collisions link1="base"/></robot>)");
  EXPECT_THAT(error_of([&] { apply_srdf(m, srdf); }), HasSubstr("link2"));
  write_text(srdf, "<robot><unclosed></robot>");
  EXPECT_THAT(error_of([&] { apply_srdf(m, srdf); }), HasSubstr("bad.srdf"));
  write_text(srdf, "<notrobot/>");
  EXPECT_THAT(error_of([&] { apply_srdf(m, srdf); }), HasSubstr("<robot>"));
  EXPECT_THAT(error_of([&] { apply_srdf(m, fx.dir / "none.srdf"); }), HasSubstr("none.srdf: file not found"));
}

TEST(ArmChain, ChecksLinksAndDescent) {
  Fixture fx;
  RobotModel m = fx.read(robot("package://my_pkg/meshes/cube.obj"));
  set_arm_chain(m, "base", "finger_a", "cli");
  EXPECT_EQ(m.arm_base, "base");
  EXPECT_EQ(m.arm_tip, "finger_a");
  set_arm_chain(m, "shoulder", "wrist", "cli");
  EXPECT_EQ(m.arm_base, "shoulder");
  EXPECT_THAT(error_of([&] { set_arm_chain(m, "base", "elbow", "robot.yaml"); }), HasSubstr("robot.yaml: arm tip"));
  EXPECT_THAT(error_of([&] { set_arm_chain(m, "elbow", "wrist", "robot.yaml"); }), HasSubstr("'elbow'"));
  EXPECT_THAT(error_of([&] { set_arm_chain(m, "wrist", "base", "robot.yaml"); }), HasSubstr("does not descend"));
  EXPECT_THAT(error_of([&] { set_arm_chain(m, "finger_a", "sensor", "robot.yaml"); }), HasSubstr("does not descend"));
  EXPECT_THAT(error_of([&] { set_arm_chain(m, "wrist", "wrist", "robot.yaml"); }), HasSubstr("same link"));
  EXPECT_EQ(m.arm_base, "shoulder");  // a rejected chain leaves the old one
}

// Issue 19: urdfdom drops a <collision> it cannot parse and goes on; we refuse the file instead,
// naming the link, the collision element and the problem. `robot()` with one element replaced.
TEST(UrdfReader, EveryCollisionElementIsReadOrRejected) {
  Fixture fx;
  const std::string good = robot("package://my_pkg/meshes/cube.obj");
  ASSERT_EQ(fx.read(good).links.at(0).collision.size(), 1u);
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  struct Case {
    std::string from, to, element, reason;
  };
  const Case cases[] = {
      {R"(xyz="0 0 0.05")", R"(xyz="0 nan 0.05")", "link 'base' collision 0", "'nan' is not a finite number"},
      {R"(rpy="0 0 0")", R"(rpy="0 0")", "link 'base' collision 0", "expected 3 numbers"},
      {R"(<box size="0.4 0.3 0.1"/>)", R"(<box size="0.4 nan 0.1"/>)", "box size", "not a finite number"},
      {R"(<box size="0.4 0.3 0.1"/>)", R"(<box size="1e9 0.3 0.1"/>)", "box size", "at most 1000 m"},
      {R"(<box size="0.4 0.3 0.1"/>)", R"(<box size="0.4 -0.3 0.1"/>)", "box size", "positive"},
      {R"(<cylinder radius="0.05" length="0.6"/>)", R"(<cylinder radius="0.05"/>)", "cylinder length",
       "expected 1 numbers"},
      {R"(<sphere radius="0.02"/>)", R"(<capsule radius="0.02" length="1"/>)", "link 'sensor' collision 0",
       "unknown geometry"},
      {R"(<link name="finger_a"/>)", R"(<link name="finger_a"><inertial><mass value="-1"/></inertial></link>)",
       "link 'finger_a' inertial mass", "positive"},
      {R"(<link name="finger_a"/>)", R"(<link name="finger_a"><inertial><mass value="nan"/></inertial></link>)",
       "link 'finger_a' inertial mass", "not a finite number"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.to);
    const std::string e = error_of([&] { fx.read(with(c.from, c.to)); });
    EXPECT_THAT(e, HasSubstr("arm.urdf"));
    EXPECT_THAT(e, HasSubstr(c.element));
    EXPECT_THAT(e, HasSubstr(c.reason));
  }
}

TEST(UrdfReader, PackagePathsMayNotLeaveTheirPackage) {
  Fixture fx;
  write_text(fx.dir / "secret.obj", kCubeObj);
  const std::string e = error_of([&] { fx.read(robot("package://my_pkg/../../secret.obj")); });
  EXPECT_THAT(e, HasSubstr("link 'wrist'"));
  EXPECT_THAT(e, HasSubstr("may not leave its package"));
  // `..` that stays inside the package is fine.
  EXPECT_NO_THROW(fx.read(robot("package://my_pkg/meshes/../meshes/cube.obj")));
}

}  // namespace
}  // namespace dmgplace::tools
