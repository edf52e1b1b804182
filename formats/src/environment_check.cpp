// The invariants `dmgplace validate` checks on an environment artifact.
#include <algorithm>
#include <cmath>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/shape_table.hpp"
#include "format_util.hpp"

namespace dmgplace::formats {
namespace {

// Slack for heights and region borders that come from float sums of the scene's poses.
constexpr double kSlack = 1e-3;
constexpr double kMaxCoordinate = kMaxGeometryExtent;

void check_grid(const FieldGrid& g, const Eigen::AlignedBox3d& volume, bool non_negative, const std::string& where,
                std::vector<std::string>& p) {
  if (g.empty()) return;
  if (!g.origin.allFinite() || !(g.resolution > 0) || !std::isfinite(g.resolution) || !(g.band > 0) ||
      !std::isfinite(g.band)) {
    p.push_back(where + ": origin, resolution and band must be finite, resolution and band positive");
    return;
  }
  if (g.dims[0] < 2 || g.dims[1] < 2 || g.dims[2] < 2 || g.values.size() != g.size()) {
    p.push_back(where + ": values do not match the grid dimensions");
    return;
  }
  std::size_t bad = 0, out_of_band = 0, negative = 0;
  const float band = float(g.band) * (1 + 1e-6f);
  for (float v : g.values) {
    if (!std::isfinite(v)) ++bad;
    else if (std::abs(v) > band) ++out_of_band;
    else if (non_negative && v < 0) ++negative;
  }
  if (bad) p.push_back(where + ": " + std::to_string(bad) + " non-finite values");
  if (out_of_band) p.push_back(where + ": " + std::to_string(out_of_band) + " values beyond the band");
  if (negative) p.push_back(where + ": " + std::to_string(negative) + " negative values");
  const auto b = g.bounds();
  if ((b.min().array() > volume.min().array() + kSlack).any() ||
      (b.max().array() < volume.max().array() - kSlack).any())
    p.push_back(where + ": grid " + detail::fmt(Eigen::Vector3d(b.min())) + " .. " +
                detail::fmt(Eigen::Vector3d(b.max())) + " does not cover the volume");
}

void check_region(const PlacementRegion& r, const EnvironmentArtifact& a, const std::string& where,
                  std::vector<std::string>& p) {
  const std::size_t cells = std::size_t(std::max(r.width, 0)) * std::size_t(std::max(r.depth, 0));
  if (!(r.resolution > 0) || !std::isfinite(r.resolution) || !std::isfinite(r.height) || !r.origin.allFinite() ||
      r.width < 1 || r.depth < 1 || r.mask.size() != cells || r.free_height.size() != cells) {
    p.push_back(where + ": needs a positive resolution, finite height and origin, and width x depth cells");
    return;
  }
  const std::size_t n = r.cell_count();
  if (n == 0) p.push_back(where + ": no cells");
  const double area = double(n) * r.resolution * r.resolution;
  if (!(std::abs(r.area - area) <= 1e-9 + 1e-9 * area)) p.push_back(where + ": area does not match its cells");
  const auto& v = a.volume;
  if (r.height < v.min().z() - kSlack || r.height > v.max().z() + kSlack)
    p.push_back(where + ": height " + detail::fmt(r.height) + " outside the volume");
  std::size_t outside = 0, unsupported = 0, bad_free = 0;
  // A supported cell's center lies on the surface: the interpolated distance there is at most a
  // region cell (surface samples, scan noise, a center past a surface's edge) plus a grid cell
  // (interpolation near edges) away from zero. A region raised by more is in mid-air.
  const double support_tol = a.sdf.empty() ? 0 : r.resolution + a.sdf.resolution;
  for (int j = 0; j < r.depth; ++j)
    for (int i = 0; i < r.width; ++i) {
      const std::size_t c = std::size_t(i) + std::size_t(r.width) * std::size_t(j);
      if (!r.mask[c]) continue;
      const Eigen::Vector2d lo = r.origin + r.resolution * Eigen::Vector2d(i, j);
      const Eigen::Vector2d hi = lo + Eigen::Vector2d::Constant(r.resolution);
      if (lo.x() < v.min().x() - kSlack || lo.y() < v.min().y() - kSlack || hi.x() > v.max().x() + kSlack ||
          hi.y() > v.max().y() + kSlack)
        ++outside;
      if (!std::isfinite(r.free_height[c]) || r.free_height[c] < 0) ++bad_free;
      if (!a.sdf.empty()) {
        const Eigen::Vector2d m = r.cell_center(i, j);
        if (std::abs(interpolated_sample(a.sdf, Eigen::Vector3d(m.x(), m.y(), r.height))) > support_tol) ++unsupported;
      }
    }
  if (outside) p.push_back(where + ": " + std::to_string(outside) + " cells outside the volume");
  if (bad_free)
    p.push_back(where + ": " + std::to_string(bad_free) + " cells with a negative or non-finite free height");
  if (unsupported)
    p.push_back(where + ": " + std::to_string(unsupported) + " cells with no surface at the region's height");
}

}  // namespace

float nearest_sample(const FieldGrid& g, const Eigen::Vector3d& p) {
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    const double u = std::round((p[a] - g.origin[a]) / g.resolution);
    idx[a] = int(std::clamp(std::isnan(u) ? 0.0 : u, 0.0, double(g.dims[std::size_t(a)] - 1)));
  }
  return g.values[std::size_t(idx[0]) +
                  std::size_t(g.dims[0]) * (std::size_t(idx[1]) + std::size_t(g.dims[1]) * std::size_t(idx[2]))];
}

float interpolated_sample(const FieldGrid& g, const Eigen::Vector3d& p) {
  int idx[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const double u = (p[a] - g.origin[a]) / g.resolution;
    const double c = std::clamp(std::isnan(u) ? 0.0 : u, 0.0, double(g.dims[std::size_t(a)] - 1));
    idx[a] = std::min(int(c), g.dims[std::size_t(a)] - 2);
    t[a] = c - idx[a];
  }
  const auto at = [&](int i, int j, int k) {
    return double(g.values[std::size_t(idx[0] + i) +
                           std::size_t(g.dims[0]) *
                               (std::size_t(idx[1] + j) + std::size_t(g.dims[1]) * std::size_t(idx[2] + k))]);
  };
  double v = 0;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        v += (i ? t[0] : 1 - t[0]) * (j ? t[1] : 1 - t[1]) * (k ? t[2] : 1 - t[2]) * at(i, j, k);
  return float(v);
}

std::vector<std::string> check_environment(const EnvironmentArtifact& a) {
  std::vector<std::string> p;
  const bool volume_ok = a.volume.min().allFinite() && a.volume.max().allFinite() &&
                         !(a.volume.min().array() >= a.volume.max().array()).any();
  if (!a.volume.min().allFinite() || !a.volume.max().allFinite()) p.push_back("volume: not finite");
  else if (!volume_ok) p.push_back("volume: min must be below max on every axis");
  else if (a.volume.min().cwiseAbs().maxCoeff() > kMaxCoordinate ||
           a.volume.max().cwiseAbs().maxCoeff() > kMaxCoordinate)
    p.push_back("volume: beyond " + detail::fmt(kMaxCoordinate) + " m from the origin");
  std::vector<OwnedShape> shapes;
  for (std::size_t i = 0; i < a.scene.objects.size(); ++i)
    for (const auto& s : a.scene.objects[i].shapes) shapes.push_back({int(i), s});
  detail::append(p, check_shapes(shapes, int(a.scene.objects.size()), "scene/shapes"));
  if (!a.scene.points.allFinite()) p.push_back("scene/points: non-finite point");
  else if (a.scene.points.size() > 0 && a.scene.points.cwiseAbs().maxCoeff() > kMaxCoordinate)
    p.push_back("scene/points: a point beyond " + detail::fmt(kMaxCoordinate) + " m from the origin");
  if (shapes.empty() && a.scene.points.rows() == 0) p.push_back("scene: no obstacles and no scan points");
  if (!volume_ok) return p;  // the checks below are relative to the volume
  check_grid(a.sdf, a.volume, !a.sdf_signed, "fields/sdf", p);
  check_grid(a.clearance, a.volume, true, "fields/clearance", p);
  for (std::size_t i = 0; i < a.regions.size(); ++i)
    check_region(a.regions[i], a, "regions[" + std::to_string(i) + "]", p);
  return p;
}

}  // namespace dmgplace::formats
