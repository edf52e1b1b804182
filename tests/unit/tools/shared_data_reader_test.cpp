// The readers on the real third-party data in ../shared/datasets (skipped when it is absent).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/io/pcd_reader.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

namespace fs = std::filesystem;
using test::shared_datasets;
using ::testing::HasSubstr;

fs::path panda_urdf() { return shared_datasets() / "panda/moveit_resources_panda_description/urdf/panda.urdf"; }
fs::path panda_srdf() { return shared_datasets() / "panda/panda_moveit_config/config/panda.srdf"; }
fs::path scenes() { return shared_datasets() / "env/motion_bench_maker/configs/scenes"; }

double diagonal(const TriMesh& m) { return (m.vertices.colwise().maxCoeff() - m.vertices.colwise().minCoeff()).norm(); }

TEST(SharedData, PandaUrdfLoadsWithCollisionMeshes) {
  DMGPLACE_REQUIRE_SHARED();
  const RobotModel m = read_urdf(panda_urdf(), {{shared_datasets() / "panda"}});
  EXPECT_EQ(m.name, "panda");
  ASSERT_EQ(m.links.size(), 12u);
  ASSERT_EQ(m.joints.size(), 11u);
  EXPECT_EQ(m.links[0].name, "panda_link0");
  const auto count = [&](JointType t) {
    return std::count_if(m.joints.begin(), m.joints.end(), [&](const Joint& j) { return j.type == t; });
  };
  EXPECT_EQ(count(JointType::Revolute), 7);
  EXPECT_EQ(count(JointType::Prismatic), 2);
  EXPECT_EQ(count(JointType::Fixed), 2);
  EXPECT_EQ(std::count_if(m.joints.begin(), m.joints.end(), [](const Joint& j) { return j.mimic >= 0; }), 1);
  const Joint& f2 = m.joints[std::size_t(m.joint_index("panda_finger_joint2"))];
  EXPECT_EQ(f2.mimic, m.joint_index("panda_finger_joint1"));
  EXPECT_DOUBLE_EQ(f2.mimic_multiplier, 1.0);
  EXPECT_TRUE(f2.axis.isApprox(-Eigen::Vector3d::UnitY()));
  const Joint& j4 = m.joints[std::size_t(m.joint_index("panda_joint4"))];
  EXPECT_DOUBLE_EQ(j4.lower, -3.1416);
  EXPECT_DOUBLE_EQ(j4.upper, 0.0873);
  EXPECT_TRUE(j4.origin.translation().isApprox(Eigen::Vector3d(0.0825, 0, 0)));

  for (const Link& l : m.links) {
    if (l.name == "panda_link8") {
      EXPECT_TRUE(l.collision.empty());
      continue;
    }
    ASSERT_EQ(l.collision.size(), 1u) << l.name;
    const Shape& s = l.collision[0];
    EXPECT_EQ(s.type, ShapeType::Mesh) << l.name;
    EXPECT_GE(s.mesh.triangles.rows(), 32) << l.name;  // the collision STLs hold 32-300 triangles
    EXPECT_LE(s.mesh.triangles.rows(), 300) << l.name;
    EXPECT_GT(diagonal(s.mesh), 0.03) << l.name;
    EXPECT_LT(diagonal(s.mesh), 0.5) << l.name;
    const MeshReport r = check_mesh(s.mesh);
    EXPECT_TRUE(r.closed_manifold()) << l.name;
    EXPECT_EQ(r.inconsistent_edges, 0u) << l.name;
    EXPECT_GT(signed_volume(s.mesh), 0) << l.name;
  }
  // The right finger's mesh is the left one turned half a turn by its collision origin.
  const Shape& right = m.links[std::size_t(m.link_index("panda_rightfinger"))].collision[0];
  EXPECT_TRUE((right.origin.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitX(), 1e-9));

  // Without package paths the URDF's own ancestor folder (named like the package) resolves them.
  EXPECT_EQ(read_urdf(panda_urdf()).links.size(), 12u);
}

TEST(SharedData, PandaSrdfAppliesAndArmChainSets) {
  DMGPLACE_REQUIRE_SHARED();
  RobotModel m = read_urdf(panda_urdf(), {{shared_datasets() / "panda"}});
  apply_srdf(m, panda_srdf());
  EXPECT_EQ(m.allowed_pairs.size(), 34u);  // 34 <disable_collisions>, all distinct
  const std::pair<int, int> adjacent{m.link_index("panda_link0"), m.link_index("panda_link1")};
  EXPECT_NE(std::find(m.allowed_pairs.begin(), m.allowed_pairs.end(), adjacent), m.allowed_pairs.end());
  set_arm_chain(m, "panda_link0", "panda_link8", panda_srdf().string());
  EXPECT_EQ(m.arm_tip, "panda_link8");
  EXPECT_THROW(set_arm_chain(m, "panda_leftfinger", "panda_link8", "x"), Error);
}

TEST(SharedData, PandaVisualColladaMatchesCollisionFrame) {
  // The visual DAEs are z-up like the STLs: read as they are, both boxes agree (a y-up
  // conversion would swap axes and miss by tens of centimetres).
  DMGPLACE_REQUIRE_SHARED();
  const fs::path dir = shared_datasets() / "panda/moveit_resources_panda_description/meshes";
  for (const std::string name : {"link0", "link1", "link3", "link5", "hand", "finger"}) {
    const TriMesh visual = read_mesh(dir / "visual" / (name + ".dae"));
    const TriMesh collision = read_mesh(dir / "collision" / (name + ".stl"));
    EXPECT_LT((visual.vertices.colwise().minCoeff() - collision.vertices.colwise().minCoeff()).norm(), 0.01) << name;
    EXPECT_LT((visual.vertices.colwise().maxCoeff() - collision.vertices.colwise().maxCoeff()).norm(), 0.01) << name;
  }
}

TEST(SharedData, YcbMeshesLoadInMetres) {
  DMGPLACE_REQUIRE_SHARED();
  for (const std::string name : {"006_mustard_bottle_textured.obj", "003_cracker_box_textured.obj"}) {
    MeshReport r;
    const TriMesh m = read_mesh(shared_datasets() / "objects/ycb" / name, {}, &r);
    EXPECT_GE(m.triangles.rows(), 16000) << name;  // 16k triangles, a few degenerate ones dropped
    EXPECT_LE(m.triangles.rows(), 16384) << name;
    EXPECT_GT(diagonal(m), 0.15) << name;
    EXPECT_LT(diagonal(m), 0.35) << name;
    EXPECT_GT(signed_volume(m), 0) << name;
    EXPECT_EQ(r.inconsistent_edges, 0u) << name;
    for (const auto& w : r.warnings) EXPECT_THAT(w, ::testing::Not(HasSubstr("--scale"))) << name;
  }
}

TEST(SharedData, MotionBenchMakerScenesLoad) {
  DMGPLACE_REQUIRE_SHARED();
  int files = 0;
  for (const std::string problem : {"bookshelf_small_panda", "table_pick_panda"})
    for (const auto& e : fs::directory_iterator(shared_datasets() / "mbm_problems" / problem)) {
      if (e.path().filename().string().rfind("scene", 0) != 0) continue;
      const Scene s = read_planning_scene_yaml(e.path());
      ++files;
      EXPECT_GE(s.objects.size(), 7u) << e.path();
      for (const auto& o : s.objects)
        for (const auto& sh : o.shapes) {
          EXPECT_NE(sh.type, ShapeType::Mesh) << e.path();
          EXPECT_GT(sh.size.maxCoeff(), 0.01) << e.path() << " " << o.name;
          EXPECT_LT(sh.origin.translation().norm(), 3.0) << e.path() << " " << o.name;
        }
    }
  EXPECT_EQ(files, 200);

  const Scene table = read_planning_scene_yaml(scenes() / "table/scene_table.yaml");
  ASSERT_EQ(table.objects.size(), 12u);
  const auto top =
      std::find_if(table.objects.begin(), table.objects.end(), [](auto& o) { return o.name == "table_top"; });
  ASSERT_NE(top, table.objects.end());
  EXPECT_TRUE(top->shapes[0].size.isApprox(Eigen::Vector3d(1.2, 2, 0.04)));
  EXPECT_TRUE(top->shapes[0].origin.translation().isApprox(Eigen::Vector3d(1.05, 0, 0.7)));
  const Scene shelf = read_planning_scene_yaml(scenes() / "bookshelf/scene_small.yaml");
  EXPECT_TRUE(shelf.objects[0].shapes[0].size.isApprox(Eigen::Vector3d(0.03, 0.14, 0)));  // Can1 [0.14, 0.03]
}

TEST(SharedData, KitchenYamlNamesItsMissingMeshes) {
  // kitchen.yaml points at objs/dishwasher.obj and objs/cupboard.obj, which the data set does not
  // ship (only the URDF's meshes/*.stl): a clear error, not an empty object.
  DMGPLACE_REQUIRE_SHARED();
  try {
    read_planning_scene_yaml(scenes() / "kitchen/kitchen.yaml");
    FAIL() << "kitchen.yaml loaded although its meshes are missing";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("kitchen.yaml"));
    EXPECT_THAT(e.what(), HasSubstr("object 'diswasher'"));
    EXPECT_THAT(e.what(), HasSubstr("objs/dishwasher.obj"));
  }
}

TEST(SharedData, KitchenAndTableBarsUrdfScenesLoad) {
  DMGPLACE_REQUIRE_SHARED();
  const Scene kitchen = read_urdf_scene(scenes() / "kitchen/kitchen.urdf");
  std::vector<std::string> names;
  for (const auto& o : kitchen.objects) names.push_back(o.name);
  EXPECT_THAT(names, ::testing::UnorderedElementsAre("cupboard", "cupboard_door_l", "cupboard_door_r",
                                                     "dishwasher_door", "kitchen_counter"));
  for (const auto& o : kitchen.objects) {
    ASSERT_EQ(o.shapes.size(), 1u);
    EXPECT_EQ(o.shapes[0].type, ShapeType::Mesh);
    EXPECT_GT(signed_volume(o.shapes[0].mesh), 0) << o.name;  // the doors' STLs are inside out: repaired
  }
  const auto door =
      std::find_if(kitchen.objects.begin(), kitchen.objects.end(), [](auto& o) { return o.name == "cupboard_door_l"; });
  EXPECT_TRUE(door->shapes[0].origin.translation().isApprox(Eigen::Vector3d(0.44637, 0.54793, 1.6839)));
  EXPECT_EQ(read_urdf_scene(scenes() / "table_bars/table_bars.urdf").objects.size(), 3u);
}

TEST(SharedData, TableScanLoadsFiniteOrganizedPoints) {
  DMGPLACE_REQUIRE_SHARED();
  const RowMatrixX3d p = read_pcd(shared_datasets() / "scans/pcl/table_scene_mug_stereo_textured.pcd");
  // 640 x 480 organized binary_compressed cloud; the NaN holes of the stereo scan are dropped.
  EXPECT_GT(p.rows(), 150000);
  EXPECT_LT(p.rows(), 640 * 480);
  EXPECT_TRUE(p.allFinite());
  EXPECT_GT(p.col(2).minCoeff(), 0.3);  // camera frame: everything in front of the camera
  EXPECT_LT(p.col(2).maxCoeff(), 4.0);
  EXPECT_EQ(read_pcd(shared_datasets() / "scans/pcl/milk.pcd").rows(), 12575);
}

TEST(SharedData, EveryFileLoads) {
  // One pass over everything readable in the data set, through the public entry points.
  DMGPLACE_REQUIRE_SHARED();
  int loaded = 0;
  for (const auto& e : fs::recursive_directory_iterator(shared_datasets())) {
    if (!e.is_regular_file()) continue;
    const fs::path& p = e.path();
    const std::string ext = p.extension().string(), stem = p.stem().string();
    SCOPED_TRACE(p.string());
    try {
      if (ext == ".stl" || ext == ".obj" || ext == ".dae" || ext == ".ply") {
        EXPECT_GT(read_mesh(p).triangles.rows(), 0);
      } else if (ext == ".pcd") {
        EXPECT_GT(read_pcd(p).rows(), 1000);
      } else if (ext == ".urdf" && stem == "panda") {
        EXPECT_EQ(read_urdf(p).joints.size(), 11u);
      } else if (ext == ".urdf") {
        EXPECT_FALSE(load_scene(p).objects.empty());
      } else if (ext == ".srdf") {
        RobotModel m = read_urdf(panda_urdf());
        apply_srdf(m, p);
        EXPECT_FALSE(m.allowed_pairs.empty());
      } else if (ext == ".yaml" && stem.rfind("request", 0) != 0 && stem != "kitchen") {
        EXPECT_FALSE(load_scene(p).objects.empty());
      } else {
        continue;
      }
      ++loaded;
    } catch (const Error& err) {
      ADD_FAILURE() << err.what();
    }
  }
  EXPECT_GE(loaded, 240);  // 33 meshes, 6 clouds, 3 URDFs, 1 SRDF, 205 scenes
}

}  // namespace
}  // namespace dmgplace::tools
