#include "dmgplace/tools/environment/geometry_regions.hpp"

#include <cmath>
#include <mutex>

#include "../system/parallel_for.hpp"

namespace dmgplace::tools {
namespace {

constexpr double kSameHeight = 1e-6;                    // crossings this close are one surface (a can on a table)
constexpr double kVolumeSlack = 1e-3;                   // a surface at V's bottom face still counts
constexpr double kJitterX = 1.3e-6, kJitterY = 0.7e-6;  // keep rays off grid-aligned edges

}  // namespace

std::vector<SurfaceSample> geometry_surface_samples(const EmbreeScene& scene, const Eigen::AlignedBox3d& volume,
                                                    const CellGrid& grid, const RegionOptions& o) {
  std::vector<SurfaceSample> out;
  const EnvironmentGeometry& geo = scene.geometry();
  if (geo.meshes.empty() || grid.nx <= 0 || grid.ny <= 0) return out;
  const double cos_tilt = std::cos(o.max_tilt_deg * M_PI / 180.0);
  const double z0 = std::min(geo.bounds().min().z(), volume.min().z()) - 1.0;
  const double z_top = volume.max().z();
  std::mutex out_mutex;
  detail::parallel_for(std::size_t(grid.ny), 0, [&](std::size_t row) {
    const int j = int(row);
    std::vector<SurfaceSample> mine;
    InsideTracker tracker(geo);
    for (int i = 0; i < grid.nx; ++i) {
      const Eigen::Vector2d c = grid.center(i, j);
      const auto hits = scene.column(c.x() + kJitterX, c.y() + kJitterY, z0, z_top + 1.0);
      tracker.reset();
      for (std::size_t h = 0; h < hits.size();) {
        // Crossings at one height form a group: a table top and the can standing on it.
        std::size_t e = h;
        bool up = false, down = false;
        double z = hits[h].z;
        for (; e < hits.size() && hits[e].z - hits[h].z <= kSameHeight; ++e) {
          tracker.cross(hits[e]);
          if (hits[e].nz >= cos_tilt) up = true, z = hits[e].z;
          if (hits[e].nz < 0) down = true;  // something starts right here
        }
        h = e;
        if (!up || down || tracker.inside()) continue;
        if (z < volume.min().z() - kVolumeSlack || z > z_top) continue;
        const double next = h < hits.size() ? hits[h].z : INFINITY;
        const double free = std::min(next, z_top) - z;
        if (free >= o.min_free_height) mine.push_back({i, j, z, float(free)});
      }
    }
    std::lock_guard<std::mutex> lock(out_mutex);
    out.insert(out.end(), mine.begin(), mine.end());
  });
  return out;
}

}  // namespace dmgplace::tools
