#include "sound_artifacts.hpp"

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/formats/sha256.hpp"
#include "dmgplace/tools/geometry/procedural_meshes.hpp"
#include "dmgplace/tools/environment/bake_environment.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "dmgplace/tools/object/dmg_builder.hpp"
#include "dmgplace/tools/object/gripper_model.hpp"
#include "dmgplace/tools/object/mass_properties.hpp"
#include "dmgplace/tools/object/placement_faces.hpp"
#include "dmgplace/tools/robot/bake_robot.hpp"

namespace dmgplace::test {

std::unique_ptr<SoundArtifacts> bake_sound_artifacts() {
  auto s = std::make_unique<SoundArtifacts>();
  const std::filesystem::path data = source_dir() / "datasets";
  tools::RobotBakeOptions ro;
  ro.urdf = s->urdf = data / "robots/dmgarm/dmgarm.urdf";
  ro.srdf = data / "robots/dmgarm/dmgarm.srdf";
  ro.arm_base = "dmgarm_link0";
  ro.arm_tip = "dmgarm_tcp";
  formats::RobotArtifact robot = tools::bake_robot(ro);
  robot.header.inputs = {{ro.urdf.string(), formats::sha256_file(ro.urdf)}};
  formats::save_robot(std::move(robot), s->robot);

  formats::ObjectArtifact obj;
  obj.mesh = tools::make_eraser_mesh();
  obj.mass = tools::compute_mass_properties(obj.mesh, 0.1, "eraser");
  obj.placement = tools::compute_placement_faces(obj.mesh, obj.mass.com, {}, "eraser");
  tools::DmgOptions dmg;
  dmg.seed_resolution = 0.02;
  dmg.angle_step_deg = 30;
  obj.dmg = tools::build_dmg(obj.mesh, tools::default_gripper(), dmg, "eraser");
  formats::save_object(std::move(obj), s->object);

  formats::EnvironmentArtifact env;
  env.scene = tools::load_scene(data / "scenes/table.yaml");
  env.volume = Eigen::AlignedBox3d(Eigen::Vector3d(0.3, -0.3, 0.4), Eigen::Vector3d(0.8, 0.3, 0.7));
  tools::EnvironmentBakeOptions eo;
  eo.resolution = 0.02;
  eo.margin = 0.9;
  eo.sdf_resolution = 0.04;
  eo.band = 0.25;
  tools::bake_environment(env, eo);
  formats::save_environment(std::move(env), s->env);
  return s;
}

}  // namespace dmgplace::test
