#include "dmgplace/tools/environment/bake_environment.hpp"

#include <cmath>
#include <string>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/environment/distance_field.hpp"
#include "dmgplace/tools/environment/embree_scene.hpp"
#include "dmgplace/tools/environment/environment_geometry.hpp"
#include "dmgplace/tools/environment/geometry_regions.hpp"
#include "dmgplace/tools/environment/scan_regions.hpp"

namespace dmgplace::tools {
namespace {

void require_positive(double v, const char* flag) {
  if (!(v > 0) || !std::isfinite(v))
    throw Error(flag, "", "must be a positive finite number, got " + std::to_string(v));
}

}  // namespace

void bake_environment(formats::EnvironmentArtifact& env, const EnvironmentBakeOptions& o) {
  require_positive(o.resolution, "--resolution");
  require_positive(o.band, "--band");
  require_positive(o.clearance_resolution, "--clearance-resolution");
  if (!(o.clearance_band >= 0) || !std::isfinite(o.clearance_band))
    throw Error("--clearance-band", "", "must be a finite length >= 0 (0: the target volume's diagonal)");
  require_positive(o.regions.split_size, "--region-split");
  if (!(o.margin >= 0) || !std::isfinite(o.margin)) throw Error("--margin", "", "must be a finite length >= 0");
  if (!(o.regions.min_free_height >= 0)) throw Error("--min-free-height", "", "must be >= 0");
  const Eigen::AlignedBox3d& v = env.volume;
  if (!v.min().allFinite() || !v.max().allFinite() || (v.min().array() >= v.max().array()).any())
    throw Error("--volume", "", "needs each min below its max");

  env.scene.points = voxel_filter(env.scene.points, o.scan_voxel);
  const EnvironmentGeometry geometry = make_environment_geometry(env.scene, o.segments);
  if (geometry.meshes.empty() && geometry.points.rows() == 0)
    throw Error("scene", "", "no obstacles and no scan points to analyse");
  const EmbreeScene scene(geometry);

  Eigen::AlignedBox3d grown = v;
  grown.min().array() -= o.margin;
  grown.max().array() += o.margin;
  // A coarser, wider grid serves the arm's fast collision layer beyond V (--margin, --sdf-resolution).
  const double sdf_resolution = o.sdf_resolution > 0 ? o.sdf_resolution : o.resolution;
  env.sdf = distance_field(scene, grid_covering(grown, sdf_resolution), o.band, o.threads, o.progress);
  env.sdf_signed = geometry.any_closed();
  // Clamped no lower than V's diagonal by default, so the clearance objective keeps rising
  // wherever a placement really is farther from everything (a band would flatten it there).
  const double clearance_band = o.clearance_band > 0 ? o.clearance_band : v.diagonal().norm();
  env.clearance =
      clearance_field(scene, grid_covering(v, o.clearance_resolution), clearance_band, o.threads, o.progress);

  RegionOptions ro = o.regions;
  ro.resolution = o.resolution;
  const CellGrid cells = cell_grid(v, ro.resolution);
  auto samples = geometry_surface_samples(scene, v, cells, ro);
  if (geometry.points.rows() > 0) {
    auto more = scan_surface_samples(geometry.points, v, cells, ro);
    samples.insert(samples.end(), more.begin(), more.end());
  }
  env.regions = build_regions(cells, std::move(samples), ro);
}

}  // namespace dmgplace::tools
