// validate --deep for ENV.h5: the stored fields and regions against exact distances to the
// stored scene, recomputed by brute force (ExactSceneDistance) at sampled grid nodes.
#include <algorithm>
#include <cmath>
#include <random>

#include "../system/parallel_for.hpp"
#include "dmgplace/tools/environment/bake_environment.hpp"
#include "dmgplace/tools/environment/environment_geometry.hpp"
#include "dmgplace/tools/validate/deep_checks.hpp"
#include "dmgplace/tools/validate/exact_scene_distance.hpp"

namespace dmgplace::tools::detail {
namespace {

// A stored node value may differ from the exact distance by float storage, the bake's arithmetic
// and, on the surface itself, which side a ray or a winding number puts the node: far below any
// error that could move a collision verdict by a sphere's rounding.
constexpr double kNodeTolerance = 1e-4;

Eigen::Vector3d node_point(const formats::FieldGrid& g, std::size_t index) {
  const std::size_t nx = std::size_t(g.dims[0]), ny = std::size_t(g.dims[1]);
  return g.origin +
         g.resolution * Eigen::Vector3d(double(index % nx), double(index / nx % ny), double(index / (nx * ny)));
}

std::size_t nearest_node(const formats::FieldGrid& g, const Eigen::Vector3d& p) {
  std::size_t idx[3];
  for (int a = 0; a < 3; ++a)
    idx[a] = std::size_t(
        std::clamp(std::round((p[a] - g.origin[a]) / g.resolution), 0.0, double(g.dims[std::size_t(a)] - 1)));
  return idx[0] + std::size_t(g.dims[0]) * (idx[1] + std::size_t(g.dims[1]) * idx[2]);
}

// Random points on the obstacles' triangles (area-weighted), moved off them by up to `offset`
// along the triangle's normal: where a field is most easily wrong.
std::vector<Eigen::Vector3d> near_surface_points(const EnvironmentGeometry& g, int count, double offset, std::mt19937_64& rng) {
  std::vector<Eigen::Vector3d> a, b, c;
  std::vector<double> area;
  for (const auto& m : g.meshes)
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
      a.push_back(m.vertices.row(m.triangles(t, 0)).transpose());
      b.push_back(m.vertices.row(m.triangles(t, 1)).transpose());
      c.push_back(m.vertices.row(m.triangles(t, 2)).transpose());
      area.push_back((b.back() - a.back()).cross(c.back() - a.back()).norm());
    }
  std::vector<Eigen::Vector3d> out;
  for (int k = 0; k < count / 2 && g.points.rows() > 0; ++k)  // scan points: half the samples
    out.push_back(g.points.row(Eigen::Index(rng() % std::uint64_t(g.points.rows()))).transpose());
  if (area.empty() || std::all_of(area.begin(), area.end(), [](double x) { return x <= 0; })) return out;
  std::discrete_distribution<std::size_t> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> u(0, 1), off(-offset, offset);
  while (int(out.size()) < count) {
    const std::size_t t = pick(rng);
    double s = u(rng), r = u(rng);
    if (s + r > 1) s = 1 - s, r = 1 - r;
    const Eigen::Vector3d n = (b[t] - a[t]).cross(c[t] - a[t]).normalized();
    out.push_back(a[t] + s * (b[t] - a[t]) + r * (c[t] - a[t]) + off(rng) * n);
  }
  return out;
}

// What a node may hold: `value`, or on a surface (where inside and outside meet) `alternative`.
struct Expected {
  double value, alternative;
};

// Stored against exact at the given nodes, both clamped to the field's band.
template <class ExactFn>
DeepCheck compare_nodes(const formats::FieldGrid& g, const std::vector<std::size_t>& nodes, const DeepOptions& o,
                        const std::string& name, const std::string& dataset, ExactFn exact_at) {
  std::vector<Expected> exact(nodes.size());
  parallel_for(nodes.size(), o.threads, [&](std::size_t i) { exact[i] = exact_at(node_point(g, nodes[i])); });
  WorstOf w;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const double stored = g.values[nodes[i]];
    const double v = std::clamp(exact[i].value, -g.band, g.band),
                 alt = std::clamp(exact[i].alternative, -g.band, g.band);
    const double miss = std::min(std::abs(stored - v), std::abs(stored - alt));
    w.add(miss, [&] {
      return "node " + fmt(node_point(g, nodes[i])) + ": stored " + fmt(stored) + ", exact " + fmt(v) +
             (alt != v ? " (or " + fmt(alt) + " on the surface)" : "");
    });
  }
  return {name, dataset, int(nodes.size()), w.worst, kNodeTolerance, "m", w.sample};
}

std::vector<std::size_t> random_nodes(const formats::FieldGrid& g, int count, std::mt19937_64& rng) {
  std::vector<std::size_t> out(static_cast<std::size_t>(count));
  for (auto& n : out) n = std::size_t(rng() % std::uint64_t(g.size()));
  return out;
}

// Nodes the stored field puts within two cells of a surface, plus nodes nearest to points on the
// geometry's own surface (which a field wrong everywhere near it cannot hide).
std::vector<std::size_t> surface_nodes(const formats::FieldGrid& g, const EnvironmentGeometry& geometry, int count,
                                       std::mt19937_64& rng) {
  std::vector<std::size_t> near;
  for (std::size_t i = 0; i < g.values.size(); ++i)
    if (std::abs(g.values[i]) <= 2 * g.resolution) near.push_back(i);
  std::vector<std::size_t> out;
  for (int k = 0; k < count / 2 && !near.empty(); ++k) out.push_back(near[rng() % near.size()]);
  for (const auto& p : near_surface_points(geometry, count - int(out.size()), g.resolution, rng))
    if (g.bounds().exteriorDistance(p) == 0) out.push_back(nearest_node(g, p));
  return out;
}

DeepCheck regions_on_surface(const formats::EnvironmentArtifact& a, const ExactSceneDistance& exact,
                             const DeepOptions& o, std::mt19937_64& rng) {
  struct Cell {
    std::size_t region;
    int i, j;
  };
  std::vector<Cell> all;
  for (std::size_t r = 0; r < a.regions.size(); ++r)
    for (int j = 0; j < a.regions[r].depth; ++j)
      for (int i = 0; i < a.regions[r].width; ++i)
        if (a.regions[r].mask[std::size_t(i) + std::size_t(a.regions[r].width) * std::size_t(j)])
          all.push_back({r, i, j});
  std::vector<Cell> cells;
  for (int k = 0; k < o.samples && !all.empty(); ++k) cells.push_back(all[rng() % all.size()]);
  std::vector<double> miss(cells.size());
  parallel_for(cells.size(), o.threads, [&](std::size_t k) {
    const auto& r = a.regions[cells[k].region];
    const Eigen::Vector2d m = r.cell_center(cells[k].i, cells[k].j);
    // The surface passes within a cell of the cell's center (a center may lie past an edge).
    miss[k] = std::abs(exact.signed_distance(Eigen::Vector3d(m.x(), m.y(), r.height), 1.0)) / r.resolution;
  });
  WorstOf w;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const auto& r = a.regions[cells[k].region];
    const Eigen::Vector2d m = r.cell_center(cells[k].i, cells[k].j);
    w.add(miss[k], [&] {
      return "region " + std::to_string(cells[k].region) + " cell (" + std::to_string(cells[k].i) + ", " +
             std::to_string(cells[k].j) + ") at " + fmt(Eigen::Vector3d(m.x(), m.y(), r.height)) + ": " +
             fmt(miss[k] * r.resolution) + " m from any obstacle";
    });
  }
  return {"region cells on an obstacle surface",
          "regions/scalars",
          int(cells.size()),
          w.worst,
          1.0,
          "region cells",
          w.sample};
}

}  // namespace

void deep_environment(const formats::EnvironmentArtifact& a, const DeepOptions& o, DeepReport& report) {
  // The bake's own tessellation of the primitives: its field is exact for that surface.
  const EnvironmentGeometry geometry = make_environment_geometry(a.scene, EnvironmentBakeOptions{}.segments);
  const ExactSceneDistance exact(geometry);
  std::mt19937_64 rng(o.seed);
  if (!a.sdf.empty()) {
    auto sdf_at = [&](const Eigen::Vector3d& p) {
      const double d = exact.signed_distance(p, a.sdf.band * 2);
      if (!a.sdf_signed) return Expected{std::abs(d), std::abs(d)};
      // On the surface the sign is a matter of rounding.
      return Expected{d, std::abs(d) <= kNodeTolerance ? -d : d};
    };
    report.checks.push_back(compare_nodes(a.sdf, random_nodes(a.sdf, o.samples, rng), o,
                                          "distance field at random grid nodes", "fields/sdf/values", sdf_at));
    report.checks.push_back(compare_nodes(a.sdf, surface_nodes(a.sdf, geometry, o.samples, rng), o,
                                          "distance field at grid nodes near the surface", "fields/sdf/values",
                                          sdf_at));
  } else {
    report.notes.push_back("no distance field stored");
  }
  if (!a.clearance.empty()) {
    auto clearance_at = [&](const Eigen::Vector3d& p) {
      // Inside a closed obstacle the clearance is 0; on its surface either answer holds.
      const double above = exact.distance_above(p, a.clearance.band * 2, p.z());
      if (exact.unsigned_distance(p, 2 * kNodeTolerance) <= kNodeTolerance) return Expected{above, 0.0};
      return exact.inside(p) ? Expected{0.0, 0.0} : Expected{above, above};
    };
    report.checks.push_back(compare_nodes(a.clearance, random_nodes(a.clearance, o.samples, rng), o,
                                          "clearance field at random grid nodes", "fields/clearance/values",
                                          clearance_at));
  } else {
    report.notes.push_back("no clearance field stored");
  }
  if (!a.regions.empty()) report.checks.push_back(regions_on_surface(a, exact, o, rng));
}

}  // namespace dmgplace::tools::detail
