#include "dmgplace/tools/environment/distance_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dmgplace/formats/error.hpp"
#include "../system/parallel_for.hpp"

namespace dmgplace::tools {
namespace {

constexpr int kBlock = 8;  // samples per block edge for the band test

// Offsets the column rays by a micrometre so they do not run exactly along grid-aligned edges.
constexpr double kJitterX = 1.3e-6, kJitterY = 0.7e-6;

struct Block {
  int lo[3], hi[3];  // sample ranges [lo, hi)
};

std::vector<Block> blocks_of(const GridSpec& g) {
  std::vector<Block> out;
  for (int k = 0; k < g.dims[2]; k += kBlock)
    for (int j = 0; j < g.dims[1]; j += kBlock)
      for (int i = 0; i < g.dims[0]; i += kBlock)
        out.push_back(
            {{i, j, k},
             {std::min(i + kBlock, g.dims[0]), std::min(j + kBlock, g.dims[1]), std::min(k + kBlock, g.dims[2])}});
  return out;
}

formats::FieldGrid empty_field(const GridSpec& g, double band) {
  formats::FieldGrid f;
  f.origin = g.origin;
  f.resolution = g.resolution;
  f.dims = g.dims;
  f.band = band;
  f.values.assign(g.size(), float(band));
  return f;
}

void require_band(double band, const char* what) {
  if (!(band > 0) || !std::isfinite(band)) throw Error(what, "", "band must be a positive finite distance");
}

// Calls fn(block, center, half_diagonal) for every block, in parallel.
template <class Fn>
void for_blocks(const GridSpec& g, int threads, const ProgressFn& progress, const char* stage, Fn&& fn) {
  const auto blocks = blocks_of(g);
  ProgressReporter report(progress, stage);
  report.add_total(blocks.size());
  detail::parallel_for(blocks.size(), threads, [&](std::size_t b) {
    const Block& bl = blocks[b];
    const Eigen::Vector3d lo = g.point(bl.lo[0], bl.lo[1], bl.lo[2]);
    const Eigen::Vector3d hi = g.point(bl.hi[0] - 1, bl.hi[1] - 1, bl.hi[2] - 1);
    fn(bl, Eigen::Vector3d(0.5 * (lo + hi)), 0.5 * (hi - lo).norm(), lo.z());
    report.done();
  });
}

}  // namespace

GridSpec grid_covering(const Eigen::AlignedBox3d& box, double resolution, std::size_t max_samples) {
  if (!(resolution > 0) || !std::isfinite(resolution))
    throw Error("--resolution", "", "must be a positive finite length");
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite())
    throw Error("--volume", "", "grid box is empty or not finite");
  GridSpec g;
  g.origin = box.min();
  g.resolution = resolution;
  double total = 1;
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil(box.sizes()[a] / resolution - 1e-9) + 1;
    total *= n;
    if (n > double(1 << 20) || total > double(max_samples))
      throw Error("--resolution", "",
                  "a grid of " + std::to_string(resolution) + " m over this volume needs more than " +
                      std::to_string(max_samples) + " samples");
    g.dims[std::size_t(a)] = std::max(2, int(n));
  }
  return g;
}

std::vector<std::uint8_t> inside_mask(const EmbreeScene& scene, const GridSpec& g) {
  std::vector<std::uint8_t> inside(g.size(), 0);
  const EnvironmentGeometry& geo = scene.geometry();
  if (!geo.any_closed()) return inside;
  const Eigen::AlignedBox3d bounds = geo.bounds();
  const double z0 = std::min(bounds.min().z(), g.origin.z()) - 1.0;
  const double z1 = g.point(0, 0, g.dims[2] - 1).z() + g.resolution;
  const std::size_t nx = std::size_t(g.dims[0]), nxy = nx * std::size_t(g.dims[1]);
  // One ray per column; walking its crossings upwards gives inside/outside for every sample.
  for (int j = 0; j < g.dims[1]; ++j)
    for (int i = 0; i < g.dims[0]; ++i) {
      const Eigen::Vector3d base = g.point(i, j, 0);
      const auto hits = scene.column(base.x() + kJitterX, base.y() + kJitterY, z0, z1);
      if (hits.empty()) continue;
      InsideTracker tracker(geo);
      std::size_t h = 0;
      for (int k = 0; k < g.dims[2]; ++k) {
        const double z = base.z() + g.resolution * k;
        while (h < hits.size() && hits[h].z < z) tracker.cross(hits[h++]);
        if (tracker.inside()) inside[std::size_t(i) + nx * std::size_t(j) + nxy * std::size_t(k)] = 1;
      }
    }
  return inside;
}

formats::FieldGrid distance_field(const EmbreeScene& scene, const GridSpec& g, double band, int threads,
                                  const ProgressFn& progress) {
  require_band(band, "--band");
  const auto inside = inside_mask(scene, g);
  formats::FieldGrid f = empty_field(g, band);
  const std::size_t nx = std::size_t(g.dims[0]), nxy = nx * std::size_t(g.dims[1]);
  for_blocks(g, threads, progress, "distance field",
             [&](const Block& b, const Eigen::Vector3d& c, double half_diag, double) {
               // Every sample of the block is within half_diag of c: if c is that much beyond the band,
               // so is the whole block.
               const double dc = scene.distance(c, band + half_diag);
               for (int k = b.lo[2]; k < b.hi[2]; ++k)
                 for (int j = b.lo[1]; j < b.hi[1]; ++j)
                   for (int i = b.lo[0]; i < b.hi[0]; ++i) {
                     const std::size_t idx = std::size_t(i) + nx * std::size_t(j) + nxy * std::size_t(k);
                     double d = band;
                     if (std::isfinite(dc)) {
                       const Eigen::Vector3d p = g.point(i, j, k);
                       // The nearest obstacle point of c bounds this sample's distance from above.
                       const double radius = std::min(band, dc + (p - c).norm() + 1e-9);
                       d = std::min(band, scene.distance(p, radius));
                     }
                     f.values[idx] = float(inside[idx] ? -d : d);
                   }
             });
  return f;
}

formats::FieldGrid clearance_field(const EmbreeScene& scene, const GridSpec& g, double band, int threads,
                                   const ProgressFn& progress) {
  require_band(band, "--clearance-band");
  const auto inside = inside_mask(scene, g);
  formats::FieldGrid f = empty_field(g, band);
  const std::size_t nx = std::size_t(g.dims[0]), nxy = nx * std::size_t(g.dims[1]);
  for_blocks(g, threads, progress, "clearance field",
             [&](const Block& b, const Eigen::Vector3d& c, double half_diag, double z_low) {
               // Geometry above a sample is a subset of the geometry above the block's lowest samples.
               const double dc = scene.distance_above(c, band + half_diag, z_low);
               for (int k = b.lo[2]; k < b.hi[2]; ++k)
                 for (int j = b.lo[1]; j < b.hi[1]; ++j)
                   for (int i = b.lo[0]; i < b.hi[0]; ++i) {
                     const std::size_t idx = std::size_t(i) + nx * std::size_t(j) + nxy * std::size_t(k);
                     if (inside[idx]) {
                       f.values[idx] = 0;
                       continue;
                     }
                     if (!std::isfinite(dc)) continue;  // stays at the band
                     const Eigen::Vector3d p = g.point(i, j, k);
                     f.values[idx] = float(std::min(band, scene.distance_above(p, band, p.z())));
                   }
             });
  return f;
}

}  // namespace dmgplace::tools
