#include <chrono>
#include <iostream>
#include "dmgplace/formats/pose_input.hpp"

#include "cli_log.hpp"
#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/tools/io/input_log.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/environment/bake_environment.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"

namespace dmgplace::cli {

OptionTable BakeEnvArgs::options() {
  return {
      {"--package-path", "package_paths", &package_paths, 0, 0, "", "Where package:// resources are found"},
      {"--resolution", "resolution", &bake.resolution, 1e-4, 1, "m", "Distance grid and region cell size"},
      {"--band", "band", &bake.band, 1e-3, 100, "m", "Distance field clamp"},
      {"--margin", "margin", &bake.margin, 0, 10, "m",
       "The distance grid covers the volume grown by this; make it reach the arm for fast checks"},
      {"--sdf-resolution", "sdf_resolution", &bake.sdf_resolution, 0, 1, "m", "Distance grid cell; 0: --resolution"},
      {"--clearance-band", "clearance_band", &bake.clearance_band, 0, 100, "m",
       "Clearance field clamp; 0: the target volume's diagonal"},
      {"--clearance-resolution", "clearance_resolution", &bake.clearance_resolution, 1e-3, 1, "m",
       "Clearance grid cell"},
      {"--scan-voxel", "scan_voxel", &bake.scan_voxel, 0, 0.1, "m",
       "Scans: one point kept per voxel of this edge; 0 keeps all"},
      {"--region-split", "region_split", &bake.regions.split_size, 1e-3, 1000, "m", "Split regions longer than this"},
      {"--min-free-height", "min_free_height", &bake.regions.min_free_height, 0, 100, "m",
       "Least free space above a region cell"},
      {"--max-tilt", "max_tilt", &bake.regions.max_tilt_deg, 0, 45, "deg",
       "A support surface's normal is within this of +z"},
      {"--min-area", "min_area", &bake.regions.min_area, 0, 100, "m^2", "Smaller support surfaces are dropped"},
      {"--threads", "", &bake.threads, 0, 256, "", "Worker threads; 0: every CPU the process may use"},
      {"--out", "", &out, 0, 0, "", "Output artifact"},
      {"--json", "", &json, 0, 0, "",
       "Print JSON: the file written, seconds taken, and the artifact's summary (as inspect --json)"},
  };
}

int run_bake_env(const BakeEnvArgs& a_in) {
  BakeEnvArgs a = a_in;
  const auto t0 = std::chrono::steady_clock::now();
  tools::InputLog log;  // every file read below goes into the header
  nlohmann::ordered_json params = option_parameters(a.options());
  params["scene"] = a.scene;
  formats::EnvironmentArtifact env;
  const auto v = parse_numbers<6>(a.volume_text, "--volume");
  params["volume"] = v;
  env.volume = Eigen::AlignedBox3d(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]));
  if ((env.volume.min().array() >= env.volume.max().array()).any())
    throw Error("--volume", "", "needs xmin,ymin,zmin,xmax,ymax,zmax with each min below its max");
  tools::SceneLoadOptions opts;
  for (const auto& p : a.package_paths) opts.urdf.package_paths.emplace_back(p);
  if (!a.frame_text.empty()) {
    const auto f = parse_numbers<6>(a.frame_text, "--frame");
    opts.frame = formats::pose_from_xyz_rpy(f, "--frame", "");
    params["frame"] = f;
  }
  env.scene = tools::load_scene(a.scene, opts);
  a.bake.progress = progress_line();
  tools::bake_environment(env, a.bake);
  // What the defaults resolved to, beside what was asked.
  params["clearance_band_used"] = env.clearance.band;
  params["sdf_resolution_used"] = a.bake.sdf_resolution > 0 ? a.bake.sdf_resolution : a.bake.resolution;
  env.header = make_header(params, {a.scene}, log.files());
  formats::save_environment(std::move(env), a.out);
  report_written(a.out, a.json, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

}  // namespace dmgplace::cli
