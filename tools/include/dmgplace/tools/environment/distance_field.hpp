#pragma once
// Distance grids of an environment built with Embree closest-point queries, limited to a band:
// blocks of 8^3 samples whose center is farther than band + half their diagonal from everything
// take the band value without per-sample queries.
#include <array>
#include <cstdint>
#include <vector>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/tools/environment/embree_scene.hpp"
#include "dmgplace/tools/system/progress.hpp"

namespace dmgplace::tools {

struct GridSpec {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double resolution = 0.01;
  std::array<int, 3> dims{0, 0, 0};
  Eigen::Vector3d point(int i, int j, int k) const { return origin + resolution * Eigen::Vector3d(i, j, k); }
  std::size_t size() const { return std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]); }
};

// Samples from box.min() every `resolution` up to at least box.max() (>= 2 per axis).
// Throws dmgplace::Error when the grid would exceed `max_samples`.
GridSpec grid_covering(const Eigen::AlignedBox3d& box, double resolution, std::size_t max_samples = 600'000'000);

// Per sample (x fastest): 1 when inside a closed mesh, by one vertical ray per column.
std::vector<std::uint8_t> inside_mask(const EmbreeScene& scene, const GridSpec& grid);

// Distance to the nearest triangle or scan point, clamped to `band`; negative inside closed
// meshes (open meshes and points give unsigned distances). threads <= 0: all cores.
formats::FieldGrid distance_field(const EmbreeScene& scene, const GridSpec& grid, double band, int threads = 0,
                                  const ProgressFn& progress = {});

// Clearance: distance to obstacle geometry strictly above each sample's height (the support
// below is ignored), 0 inside closed meshes, clamped to `band`.
formats::FieldGrid clearance_field(const EmbreeScene& scene, const GridSpec& grid, double band, int threads = 0,
                                   const ProgressFn& progress = {});

}  // namespace dmgplace::tools
