#include <chrono>
#include <iostream>

#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/tools/io/input_log.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/object/dmg_builder.hpp"
#include "dmgplace/tools/object/gripper_model.hpp"
#include "dmgplace/tools/object/mass_properties.hpp"
#include "dmgplace/tools/object/placement_faces.hpp"

namespace dmgplace::cli {

int run_bake_object(const BakeObjectArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  tools::InputLog log;  // every file read below goes into the header
  tools::MeshReadOptions opts;
  opts.scale = a.scale;
  tools::MeshReport report;
  formats::ObjectArtifact obj;
  obj.mesh = tools::read_mesh(a.mesh, opts, &report);
  for (const auto& w : report.warnings) std::cerr << "warning: " << a.mesh << ": " << w << "\n";
  obj.mass = tools::compute_mass_properties(obj.mesh, a.mass, a.mesh);
  if (a.com) {
    obj.mass.com = Eigen::Vector3d((*a.com)[0], (*a.com)[1], (*a.com)[2]);
    obj.mass.com_overridden = true;
  }
  tools::FaceOptions place;
  place.merge_angle = a.face_merge_angle;
  place.margin = a.stability_margin;
  obj.placement = tools::compute_placement_faces(obj.mesh, obj.mass.com, place, a.mesh);
  const auto gripper = a.gripper.empty() ? tools::default_gripper() : tools::load_gripper_yaml(a.gripper);
  tools::DmgOptions dmg;
  dmg.seed_resolution = a.seed_resolution;
  dmg.angle_step_deg = a.angle_step;
  dmg.normal_threshold = a.normal_threshold;
  obj.dmg = tools::build_dmg(obj.mesh, gripper, dmg, a.mesh);
  obj.grasp_graph = formats::build_grasp_graph_table(obj.dmg, a.rotation_weight);

  nlohmann::json params = {{"mesh", a.mesh},
                           {"scale", a.scale},
                           {"mass", a.mass},
                           {"gripper", a.gripper.empty() ? "built-in dmgarm hand" : a.gripper},
                           {"seed_resolution", a.seed_resolution},
                           {"angle_step", a.angle_step},
                           {"normal_threshold", a.normal_threshold},
                           {"face_merge_angle", a.face_merge_angle},
                           {"stability_margin", a.stability_margin},
                           {"rotation_weight", a.rotation_weight}};
  if (a.com) params["com"] = *a.com;
  std::vector<std::filesystem::path> inputs{a.mesh};
  if (!a.gripper.empty()) inputs.emplace_back(a.gripper);
  obj.header = make_header(params, inputs, log.files());
  formats::save_object(std::move(obj), a.out);
  report_written(a.out, a.json, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

}  // namespace dmgplace::cli
