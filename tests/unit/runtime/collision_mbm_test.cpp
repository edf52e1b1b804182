// The fast layer against FCL on real data: the Panda (collision meshes, SRDF) in
// MotionBenchMaker scenes, 100k random configurations in all.
#include <gtest/gtest.h>

#include <random>

#include "analytic_sdf.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"
#include "test_support.hpp"

using namespace dmgplace;

TEST(CollisionMbm, FastLayerNeverSaysFreeWhereFclCollidesOnPandaScenes) {
  DMGPLACE_REQUIRE_SHARED();
  auto shared = test::shared_datasets();
  tools::UrdfOptions o;
  o.package_paths.push_back(shared / "panda");
  RobotModel model = tools::read_urdf(shared / "panda/moveit_resources_panda_description/urdf/panda.urdf", o);
  tools::apply_srdf(model, shared / "panda/panda_moveit_config/config/panda.srdf");
  std::vector<formats::LinkSphere> spheres;
  for (std::size_t l = 0; l < model.links.size(); ++l)
    for (const auto& s : tools::cover_with_spheres(model.links[l].collision)) spheres.push_back({int(l), s.center, s.radius});
  runtime::Kinematics kin(model, "panda_link0", "panda_hand");
  kin.set_joint_value("panda_finger_joint1", 0.04);
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0, 1);
  long total = 0, exact_free = 0, fast_free = 0, full = 0;
  for (auto scene_file : {"mbm_problems/bookshelf_small_panda/scene0001.yaml", "mbm_problems/table_pick_panda/scene0001.yaml"}) {
    Scene scene = tools::load_scene(shared / scene_file);
    auto sdf = test::analytic_sdf(scene, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.3), Eigen::Vector3d(1.6, 1.2, 1.7)),
                                  0.02, 0.25);
    runtime::SphereFieldChecker fast(kin, spheres, sdf, 0.25);
    runtime::ExactChecker exact(kin, scene);
    runtime::TwoLayerChecker both(fast, exact);
    for (int i = 0; i < 50000; ++i) {
      Eigen::VectorXd q(7);
      for (int j = 0; j < 7; ++j) q[j] = kin.lower()[j] + u(rng) * (kin.upper()[j] - kin.lower()[j]);
      const bool f = fast.is_free(q);
      const auto e = exact.check(q);
      ++total;
      fast_free += f;
      exact_free += e.free();
      ASSERT_FALSE(f && !e.free()) << scene_file << ": fast layer said free where FCL finds " << e.contact
                                   << " at q = " << q.transpose();
      ASSERT_EQ(both.is_free(q), e.free()) << scene_file;
    }
    full += both.counters().exact_full.load();
  }
  EXPECT_GT(exact_free, 0);
  EXPECT_LT(full, total / 2) << "the sphere layer must settle most environment queries itself";
  RecordProperty("configurations", int(total));
  RecordProperty("exact_free", int(exact_free));
  RecordProperty("fast_free", int(fast_free));
  RecordProperty("full_exact_checks", int(full));
}
