#include "dmgplace/tools/environment/region_builder.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace dmgplace::tools {
namespace {

struct Cell {
  int i, j;
  double z;
  float free_height;
};
using Cells = std::vector<Cell>;

// 8-connected components of `cells` (which lie on one height level).
std::vector<Cells> components(const Cells& cells) {
  if (cells.empty()) return {};
  int i0 = cells[0].i, i1 = i0, j0 = cells[0].j, j1 = j0;
  for (const auto& c : cells) {
    i0 = std::min(i0, c.i), i1 = std::max(i1, c.i);
    j0 = std::min(j0, c.j), j1 = std::max(j1, c.j);
  }
  const int w = i1 - i0 + 1, d = j1 - j0 + 1;
  std::vector<int> at(std::size_t(w) * std::size_t(d), -1);
  auto slot = [&](int i, int j) -> int& { return at[std::size_t(i - i0) + std::size_t(w) * std::size_t(j - j0)]; };
  for (std::size_t n = 0; n < cells.size(); ++n)
    if (slot(cells[n].i, cells[n].j) < 0) slot(cells[n].i, cells[n].j) = int(n);
  std::vector<char> seen(cells.size(), 0);
  std::vector<Cells> out;
  std::vector<int> stack;
  for (std::size_t s = 0; s < cells.size(); ++s) {
    if (seen[s] || slot(cells[s].i, cells[s].j) != int(s)) continue;  // duplicates fold into the first
    Cells comp;
    seen[s] = 1;
    stack.assign(1, int(s));
    while (!stack.empty()) {
      const Cell c = cells[std::size_t(stack.back())];
      stack.pop_back();
      comp.push_back(c);
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int ni = c.i + di, nj = c.j + dj;
          if (ni < i0 || ni > i1 || nj < j0 || nj > j1) continue;
          const int m = slot(ni, nj);
          if (m >= 0 && !seen[std::size_t(m)]) {
            seen[std::size_t(m)] = 1;
            stack.push_back(m);
          }
        }
    }
    out.push_back(std::move(comp));
  }
  return out;
}

// Halves a surface at the median cell along its longer side until no piece is longer than
// `limit`, so pieces have about equal cell counts; each piece is re-split into its components.
void split(const Cells& cells, double res, double limit, std::vector<Cells>& out) {
  int lo[2] = {cells[0].i, cells[0].j}, hi[2] = {lo[0], lo[1]};
  for (const auto& c : cells) {
    lo[0] = std::min(lo[0], c.i), hi[0] = std::max(hi[0], c.i);
    lo[1] = std::min(lo[1], c.j), hi[1] = std::max(hi[1], c.j);
  }
  const int ext[2] = {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1};
  if (std::max(ext[0], ext[1]) * res <= limit * (1 + 1e-9) || cells.size() < 2) {
    out.push_back(cells);
    return;
  }
  const int axis = ext[0] >= ext[1] ? 0 : 1;
  auto coord = [axis](const Cell& c) { return axis == 0 ? c.i : c.j; };
  std::vector<int> cs;
  cs.reserve(cells.size());
  for (const auto& c : cells) cs.push_back(coord(c));
  std::nth_element(cs.begin(), cs.begin() + std::ptrdiff_t(cs.size() / 2), cs.end());
  const int cut = std::max(cs[cs.size() / 2], lo[axis] + 1);  // both halves non-empty
  Cells a, b;
  for (const auto& c : cells) (coord(c) < cut ? a : b).push_back(c);
  for (const Cells* half : {&a, &b})
    for (const auto& comp : components(*half)) split(comp, res, limit, out);
}

formats::PlacementRegion make_region(const Cells& cells, const CellGrid& grid, double height, int surface) {
  int i0 = cells[0].i, i1 = i0, j0 = cells[0].j, j1 = j0;
  for (const auto& c : cells) {
    i0 = std::min(i0, c.i), i1 = std::max(i1, c.i);
    j0 = std::min(j0, c.j), j1 = std::max(j1, c.j);
  }
  formats::PlacementRegion r;
  r.height = height;
  r.resolution = grid.resolution;
  r.origin = grid.origin + grid.resolution * Eigen::Vector2d(i0, j0);
  r.width = i1 - i0 + 1;
  r.depth = j1 - j0 + 1;
  r.mask.assign(std::size_t(r.width) * std::size_t(r.depth), 0);
  r.free_height.assign(r.mask.size(), 0.f);
  for (const auto& c : cells) {
    const std::size_t k = std::size_t(c.i - i0) + std::size_t(r.width) * std::size_t(c.j - j0);
    r.mask[k] = 1;
    r.free_height[k] = c.free_height;
  }
  r.area = double(r.cell_count()) * grid.resolution * grid.resolution;
  r.surface = surface;
  return r;
}

}  // namespace

CellGrid cell_grid(const Eigen::AlignedBox3d& volume, double resolution) {
  CellGrid g;
  g.origin = volume.min().head<2>();
  g.resolution = resolution;
  g.nx = std::max(0, int(std::floor(volume.sizes().x() / resolution + 1e-6)));
  g.ny = std::max(0, int(std::floor(volume.sizes().y() / resolution + 1e-6)));
  return g;
}

std::vector<formats::PlacementRegion> build_regions(const CellGrid& grid, std::vector<SurfaceSample> samples,
                                                    const RegionOptions& o) {
  // Fully ordered so the regions do not depend on the order the samples were found in.
  std::sort(samples.begin(), samples.end(), [](const SurfaceSample& a, const SurfaceSample& b) {
    return a.z != b.z ? a.z < b.z : a.j != b.j ? a.j < b.j : a.i < b.i;
  });
  std::vector<formats::PlacementRegion> out;
  int surface = 0;
  for (std::size_t s = 0; s < samples.size();) {
    // A height level: samples within level_tolerance of its lowest one.
    std::size_t e = s;
    Cells level;
    while (e < samples.size() && samples[e].z - samples[s].z <= o.level_tolerance) {
      level.push_back({samples[e].i, samples[e].j, samples[e].z, samples[e].free_height});
      ++e;
    }
    s = e;
    for (const auto& comp : components(level)) {
      const double area = double(comp.size()) * grid.resolution * grid.resolution;
      if (area < o.min_area) continue;
      double height = 0;
      for (const auto& c : comp) height += c.z;
      height /= double(comp.size());
      std::vector<Cells> pieces;
      split(comp, grid.resolution, o.split_size, pieces);
      for (const auto& p : pieces) out.push_back(make_region(p, grid, height, surface));
      ++surface;
    }
  }
  return out;
}

}  // namespace dmgplace::tools
