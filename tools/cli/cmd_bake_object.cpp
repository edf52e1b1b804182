#include <algorithm>
#include <chrono>
#include <iostream>

#include "cli_log.hpp"
#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/tools/io/input_log.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/object/gripper_model.hpp"
#include "dmgplace/tools/object/mass_properties.hpp"
#include "dmgplace/tools/scan/scan_object.hpp"

namespace dmgplace::cli {
namespace {

bool is_scan(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".pcd";
}

// The segmentation and reconstruction, as the bake reports them (stdout, or --json's "scan").
nlohmann::ordered_json scan_report(const tools::ScanObject& s) {
  const auto& g = s.segmented;
  const auto& r = s.reconstruction;
  nlohmann::ordered_json clusters = nlohmann::ordered_json::array();
  for (const auto& c : g.clusters)
    clusters.push_back({{"points", c.points},
                        {"centroid", {c.centroid.x(), c.centroid.y(), c.centroid.z()}},
                        {"extent", {c.extent.x(), c.extent.y(), c.extent.z()}}});
  return {{"input_points", g.input_points},
          {"cropped_points", g.cropped_points},
          {"plane_removed", g.plane_removed},
          {"plane_points", g.plane_points},
          {"clusters", clusters},
          {"chosen_cluster", g.chosen},
          {"object_points", s.points.size()},
          {"normals", g.orientation},
          {"point_spacing", r.point_spacing},
          {"seen_distance", r.seen_distance},
          {"seen_fraction", r.seen_fraction},
          {"origin_in_scan", {s.origin_in_scan.x(), s.origin_in_scan.y(), s.origin_in_scan.z()}},
          {"notes", g.notes},
          {"warnings", r.warnings}};
}

}  // namespace

OptionTable BakeObjectArgs::options() {
  return {
      {"--scale", "scale", &scale, 1e-6, 1e6, "", "Unit scale to metres (0.001 for millimetre files); scans too"},
      {"--mass", "mass", &mass, 0, 1e5, "kg", "Mass; 0: volume x 1000 kg/m^3"},
      {"--gripper", "gripper", &gripper, 0, 0, "", "Gripper YAML; empty: the built-in dmgarm hand"},
      {"--seed-resolution", "seed_resolution", &dmg.seed_resolution, 1e-4, 1, "m",
       "DMG patch size (supervoxel seed with --dmg-from points)"},
      {"--angle-step", "angle_step", &dmg.angle_step_deg, 0.1, 180, "deg", "DMG finger angle step; divides 360"},
      {"--normal-threshold", "normal_threshold", &dmg.normal_threshold, 1e-6, 4, "",
       "DMG facets: adjacent patches join when |n_i - n_j|^2 is below this"},
      {"--crease-angle", "crease_angle", &dmg.crease_angle, 1e-3, 3.1, "rad",
       "DMG: mesh edges sharper than this bound patches"},
      {"--friction-angle", "friction_angle", &dmg.friction_angle, 1e-3, 1.5, "rad",
       "DMG: the opposite contact's normal within this of antipodal"},
      {"--face-merge-angle", "face_merge_angle", &faces.merge_angle, 0, 1.5, "rad",
       "Placement faces: hull facets within this of a seed's normal merge"},
      {"--stability-margin", "stability_margin", &faces.margin, 0, 1, "m",
       "Placement faces: COM margin inside the support polygon"},
      {"--rotation-weight", "rotation_weight", &rotation_weight, 1e-6, 100, "m/rad",
       "Grasp graph: cost of in-hand rotation against sliding"},
      {"--whole-crop", "whole_crop", &segment.whole_crop, 0, 0, "",
       "Scans: the points in --crop are the object (no plane removal, no clusters)"},
      {"--support-plane",
       "support_plane",
       &support_plane,
       0,
       0,
       "",
       "Scans: remove the dominant plane (auto: when wider than the object on it)",
       {"auto", "remove", "keep"}},
      {"--plane-distance", "plane_distance", &segment.plane_distance, 1e-4, 0.1, "m",
       "Scans: RANSAC inlier distance of the support plane"},
      {"--cluster-tolerance", "cluster_tolerance", &segment.cluster_tolerance, 1e-4, 0.5, "m",
       "Scans: Euclidean clustering gap"},
      {"--min-cluster-points", "min_cluster_points", &segment.min_cluster_points, 1, 1e7, "",
       "Scans: smaller clusters are noise"},
      {"--cluster", "cluster", &segment.cluster, -1, 1e6, "",
       "Scans: take cluster N (largest first); -1: the only one, or --cluster-near"},
      {"--smoothing-radius", "smoothing_radius", &segment.smoothing_radius, 0, 0.1, "m",
       "Scans: moving-least-squares smoothing and normals within this radius; 0: off"},
      {"--normal-neighbours", "normal_neighbours", &segment.normal_neighbours, 3, 200, "",
       "Scans: neighbours per normal estimate without smoothing"},
      {"--reconstruct",
       "reconstruct",
       &reconstruct_method,
       0,
       0,
       "",
       "Scans: surface from the points (hull for convex objects seen from few sides)",
       {"poisson", "hull"}},
      {"--poisson-depth", "poisson_depth", &reconstruct.poisson_depth, 4, 12, "", "Scans: Poisson octree depth"},
      {"--poisson-samples-per-node", "poisson_samples_per_node", &reconstruct.poisson_samples_per_node, 1, 50, "",
       "Scans: Poisson smoothing (higher for noisier scans)"},
      {"--seen-distance", "seen_distance", &reconstruct.seen_distance, 0, 0.1, "m",
       "Scans: surface this near a scan point counts as seen; 0: 3 x point spacing"},
      {"--dmg-from",
       "dmg_from",
       &dmg_from,
       0,
       0,
       "",
       "Scans: DMG patches from the reconstructed mesh, or supervoxels of the points (the original's)",
       {"mesh", "points"}},
      {"--out", "", &out, 0, 0, "", "Output artifact"},
      {"--json", "", &json, 0, 0, "",
       "Print JSON: the file written, seconds taken, the scan's segmentation, the artifact's summary"},
  };
}

namespace {
// The scans' options from the command line (crop, cluster choice, reconstruction), each recorded
// in the header's parameters.
tools::ScanObjectOptions scan_options(const BakeObjectArgs& a, nlohmann::ordered_json& params) {
  tools::ScanObjectOptions so;
  so.scale = a.scale;
  so.segment = a.segment;
  so.segment.support_plane = a.support_plane == "remove" ? tools::SupportPlane::Remove
                             : a.support_plane == "keep" ? tools::SupportPlane::Keep
                                                         : tools::SupportPlane::Auto;
  if (!a.crop_text.empty()) {
    const auto c = parse_numbers<6>(a.crop_text, "--crop");
    so.segment.crop = Eigen::AlignedBox3d(Eigen::Vector3d(c[0], c[1], c[2]), Eigen::Vector3d(c[3], c[4], c[5]));
    if (so.segment.crop->isEmpty()) throw Error("--crop", "", "min corner must not exceed the max corner");
    params["crop"] = c;
  }
  if (!a.near_text.empty()) {
    const auto p = parse_numbers<3>(a.near_text, "--cluster-near");
    so.segment.cluster_near = Eigen::Vector3d(p[0], p[1], p[2]);
    params["cluster_near"] = p;
  }
  if (a.segment.whole_crop && !so.segment.crop) throw Error("--whole-crop", "", "needs --crop");
  so.reconstruct = a.reconstruct;
  so.reconstruct.method = a.reconstruct_method == "hull" ? tools::Reconstruction::Hull : tools::Reconstruction::Poisson;
  return so;
}

// The object from its scans, what segmentation and reconstruction decided logged.
tools::ScanObject object_from_scans(const BakeObjectArgs& a, nlohmann::ordered_json& params,
                                    nlohmann::ordered_json& extra) {
  const std::string& name = a.inputs.front();
  tools::ScanObject scan = tools::object_from_scans({a.inputs.begin(), a.inputs.end()}, scan_options(a, params));
  params["object_origin_in_scan"] = {scan.origin_in_scan.x(), scan.origin_in_scan.y(), scan.origin_in_scan.z()};
  extra["scan"] = scan_report(scan);
  for (const auto& w : scan.reconstruction.warnings) log_warning(name + ": " + w);
  for (const auto& n : scan.segmented.notes) log_info(name + ": " + n);
  char line[256];
  std::snprintf(line, sizeof line,
                "%zu object points, surface %.0f%% seen (within %.1f mm of a point), object frame at (%.3f, %.3f, "
                "%.3f) in the scan",
                scan.points.size(), 100 * scan.reconstruction.seen_fraction, 1e3 * scan.reconstruction.seen_distance,
                scan.origin_in_scan.x(), scan.origin_in_scan.y(), scan.origin_in_scan.z());
  log_info(name + ": " + line);
  return scan;
}
}  // namespace

int run_bake_object(const BakeObjectArgs& a_in) {
  const auto t0 = std::chrono::steady_clock::now();
  BakeObjectArgs a = a_in;
  tools::InputLog log;  // every file read below goes into the header
  nlohmann::ordered_json params = option_parameters(a.options());
  params["inputs"] = a.inputs;
  if (a.gripper.empty()) params["gripper"] = "built-in dmgarm hand";
  const bool scans = std::any_of(a.inputs.begin(), a.inputs.end(), is_scan);
  if (scans && !std::all_of(a.inputs.begin(), a.inputs.end(), is_scan))
    throw Error(a.inputs.front(), "", "give one mesh, or PCD scans only: not both");
  if (!scans && a.inputs.size() != 1)
    throw Error(a.inputs.front(), "", "one mesh per object (several inputs must all be .pcd scans)");
  const std::string& name = a.inputs.front();

  formats::ObjectArtifact obj;
  nlohmann::ordered_json extra = nlohmann::ordered_json::object();
  std::optional<tools::ScanObject> scan;
  if (scans) {
    scan = object_from_scans(a, params, extra);
    obj.mesh = scan->mesh;
  } else {
    if (a.dmg_from == "points") throw Error("--dmg-from", "", "points needs PCD scans");
    tools::MeshReadOptions opts;
    opts.scale = a.scale;
    tools::MeshReport report;
    obj.mesh = tools::read_mesh(name, opts, &report);
    for (const auto& w : report.warnings) log_warning(name + ": " + w);
  }
  obj.mass = tools::compute_mass_properties(obj.mesh, a.mass, name);
  if (!a.com_text.empty()) {
    const auto c = parse_numbers<3>(a.com_text, "--com");
    obj.mass.com = Eigen::Vector3d(c[0], c[1], c[2]);
    obj.mass.com_overridden = true;
    params["com"] = c;
  }
  obj.placement = tools::compute_placement_faces(obj.mesh, obj.mass.com, a.faces, name);
  const auto gripper = a.gripper.empty() ? tools::default_gripper() : tools::load_gripper_yaml(a.gripper);
  a.dmg.progress = progress_line();
  obj.dmg = scan && a.dmg_from == "points"
                ? tools::build_dmg_from_points(obj.mesh, scan->points, scan->normals, gripper, a.dmg, name)
                : tools::build_dmg(obj.mesh, gripper, a.dmg, name);
  obj.grasp_graph = formats::build_grasp_graph_table(obj.dmg, a.rotation_weight);

  std::vector<std::filesystem::path> inputs(a.inputs.begin(), a.inputs.end());
  if (!a.gripper.empty()) inputs.emplace_back(a.gripper);
  obj.header = make_header(params, inputs, log.files());
  // Never write what every loader would refuse (a reconstruction can pass each step and still be unsound).
  if (const auto problems = formats::check_object(obj); !problems.empty())
    throw Error(name, "",
                "the baked object is not sound: " + problems.front() + (problems.size() > 1 ? " (and more)" : ""));
  formats::save_object(std::move(obj), a.out);
  report_written(a.out, a.json, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), extra);
  return 0;
}

}  // namespace dmgplace::cli
