#include <chrono>
#include <iostream>
#include "dmgplace/formats/pose_input.hpp"

#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/tools/io/input_log.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/env/bake_environment.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"

namespace dmgplace::cli {

int run_bake_env(const BakeEnvArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  tools::InputLog log;  // every file read below goes into the header
  formats::EnvironmentArtifact env;
  const auto& v = a.volume;
  env.volume = Eigen::AlignedBox3d(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]));
  if (!env.volume.min().allFinite() || !env.volume.max().allFinite() ||
      (env.volume.min().array() >= env.volume.max().array()).any())
    throw Error("--volume", "", "needs xmin,ymin,zmin,xmax,ymax,zmax with each min below its max");
  tools::SceneLoadOptions opts;
  for (const auto& p : a.package_paths) opts.urdf.package_paths.emplace_back(p);
  if (a.frame) {
    opts.frame = formats::pose_from_xyz_rpy(*a.frame, "--frame", "");
  }
  env.scene = tools::load_scene(a.scene, opts);
  tools::EnvBakeOptions bake;
  bake.threads = a.threads;
  bake.resolution = a.resolution;
  bake.band = a.band;
  bake.clearance_band = a.clearance_band;
  bake.regions.split_size = a.region_split;
  bake.regions.min_free_height = a.min_free_height;
  bake.margin = a.margin;
  bake.sdf_resolution = a.sdf_resolution;
  tools::bake_environment(env, bake);
  nlohmann::json params = {{"scene", a.scene},       {"volume", a.volume},
                           {"resolution", a.resolution}, {"band", a.band},
                           {"clearance_band", env.clearance.band}, {"region_split", a.region_split},
                           {"min_free_height", a.min_free_height}, {"margin", a.margin},
                           {"sdf_resolution", a.sdf_resolution > 0 ? a.sdf_resolution : a.resolution}};
  if (a.frame) params["frame"] = *a.frame;
  env.header = make_header(params, {a.scene}, log.files());
  formats::save_environment(std::move(env), a.out);
  report_written(a.out, a.json, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

}  // namespace dmgplace::cli
