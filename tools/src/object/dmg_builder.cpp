#include "dmgplace/tools/object/dmg_builder.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dmg_gripper_check.hpp"
#include "dmg_internal.hpp"
#include "dmgplace/formats/error.hpp"
#include "embree_mesh.hpp"

namespace dmgplace::tools {
namespace {

constexpr double kSamplesPerSeed = 5;  // sample spacing = seed / this
constexpr double kMaxSamples = 4e6;    // refuse a seed so small the sampling explodes

struct Opposite {
  Eigen::Vector3d point;
  int patch = -1;
};

void check_options(const DmgOptions& o, const std::string& file) {
  if (!(o.seed_resolution > 0) || !std::isfinite(o.seed_resolution))
    throw Error(file, "--seed-resolution", "must be positive");
  const double k = 360.0 / o.angle_step_deg;
  if (!(o.angle_step_deg > 0) || std::abs(k - std::round(k)) > 1e-9 || k < 1)
    throw Error(file, "--angle-step", "must divide 360 degrees into a whole number of steps");
  if (!(o.normal_threshold > 0) || !(o.normal_threshold <= 4))
    throw Error(file, "--normal-threshold", "must be in (0, 4]");
  if (!(o.crease_angle > 0) || !(o.friction_angle > 0))
    throw Error(file, "dmg", "crease and friction angles must be positive");
}

// Contiguous runs of valid angle indices, wrap-around merged: (first, count).
std::vector<std::pair<int, int>> intervals(const std::vector<char>& valid) {
  const int k = int(valid.size());
  std::vector<std::pair<int, int>> out;
  if (std::all_of(valid.begin(), valid.end(), [](char v) { return v; })) return {{0, k}};
  int start = 0;
  while (valid[start]) ++start;  // an invalid angle exists: runs start after one
  for (int i = 1; i <= k; ++i) {
    const int a = (start + i) % k;
    if (!valid[a]) continue;
    if (valid[(a + k - 1) % k]) out.back().second++;
    else out.push_back({a, 1});
  }
  return out;
}

bool intervals_meet(const formats::DmgNode& a, const formats::DmgNode& b, int k) {
  for (int i = 0; i < a.angle_count; ++i)
    if ((a.first_angle + i - b.first_angle + 2 * k) % k < b.angle_count) return true;
  return false;
}

formats::Dmg assemble(const TriMesh& mesh, const formats::GripperModel& gripper, const DmgOptions& o,
                      const detail::SurfaceSamples& samples, const detail::SampleGrid& grid,
                      const detail::Patches& patches);

}  // namespace

formats::Dmg build_dmg(const TriMesh& mesh, const formats::GripperModel& gripper, const DmgOptions& o,
                       const std::string& file) {
  check_options(o, file);
  if (mesh.empty()) throw Error(file, "mesh", "empty");
  double area = 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose();
    area += 0.5 * (mesh.vertices.row(mesh.triangles(t, 1)).transpose() - a)
                      .cross(mesh.vertices.row(mesh.triangles(t, 2)).transpose() - a)
                      .norm();
  }
  const double spacing = o.seed_resolution / kSamplesPerSeed;
  if (area / (spacing * spacing) > kMaxSamples)
    throw Error(file, "--seed-resolution", "too small for this object (over 4 million surface samples)");
  const auto samples = detail::sample_surface(mesh, spacing);
  if (samples.position.empty()) throw Error(file, "mesh", "no surface area to sample");
  const detail::SampleGrid grid(samples.position, 2 * spacing);
  const auto patches = detail::segment_patches(mesh, samples, grid, o.seed_resolution, o.crease_angle);
  return assemble(mesh, gripper, o, samples, grid, patches);
}

formats::Dmg build_dmg_from_points(const TriMesh& mesh, const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<Eigen::Vector3d>& normals, const formats::GripperModel& gripper,
                                   const DmgOptions& o, const std::string& file) {
  check_options(o, file);
  if (mesh.empty()) throw Error(file, "mesh", "empty");
  if (points.size() != normals.size() || points.empty())
    throw Error(file, "points", "no points, or not one normal per point");
  detail::SurfaceSamples samples;
  const auto patches = detail::supervoxel_patches(mesh, points, normals, o.seed_resolution, samples);
  if (patches.size.empty()) throw Error(file, "points", "no supervoxel: too few points for --seed-resolution");
  const detail::SampleGrid grid(samples.position, 2 * samples.spacing);
  return assemble(mesh, gripper, o, samples, grid, patches);
}

namespace {

// Opposite contact per patch: the other finger's ray through the object along -n, kept where the
// two contacts are antipodal enough to hold.
std::vector<Opposite> opposite_contacts(const detail::EmbreeMesh& embree, const formats::GripperModel& gripper,
                                        const detail::SampleGrid& grid, const detail::Patches& patches, double spacing,
                                        double inset, double cos_friction) {
  std::vector<Opposite> opposite(patches.size.size());
  for (std::size_t i = 0; i < opposite.size(); ++i) {
    const Eigen::Vector3d& p = patches.position[i];
    const Eigen::Vector3d& n = patches.normal[i];
    const auto hit = embree.cast(p - inset * n, -n, gripper.max_opening);
    if (!hit) continue;
    const Eigen::Vector3d q = p - (inset + hit->distance) * n;
    if ((p - q).norm() > gripper.max_opening) continue;
    const int s = grid.nearest(q, 4 * spacing);
    if (s < 0) continue;
    const int op = patches.of_sample[s];
    if (-patches.normal[op].dot(n) < cos_friction) continue;  // not antipodal enough to hold
    opposite[i] = {q, op};
  }
  return opposite;
}

// Edges: both fingers can slide. Adjacent patches of one facet with a common valid angle, whose
// opposite contacts lie on the same or adjacent patches of one facet.
void add_edges(formats::Dmg& dmg, const detail::Patches& patches, const detail::Facets& facets,
               const std::vector<Opposite>& opposite, const std::vector<std::vector<int>>& nodes_of_patch) {
  const int k = dmg.angle_count();
  auto adjacent = [&](int a, int b) {
    return a == b || std::binary_search(patches.neighbours[a].begin(), patches.neighbours[a].end(), b);
  };
  for (std::size_t i = 0; i < nodes_of_patch.size(); ++i)
    for (int j : patches.neighbours[i]) {
      if (j <= int(i) || facets.of_patch[i] != facets.of_patch[j]) continue;
      const int oi = opposite[i].patch, oj = opposite[j].patch;
      if (oi < 0 || oj < 0 || facets.of_patch[oi] != facets.of_patch[oj] || !adjacent(oi, oj)) continue;
      for (int a : nodes_of_patch[i])
        for (int b : nodes_of_patch[j])
          if (intervals_meet(dmg.nodes[a], dmg.nodes[b], k)) {
            dmg.edges.push_back({a, b});
            dmg.edges.push_back({b, a});
          }
    }
}

formats::Dmg assemble(const TriMesh& mesh, const formats::GripperModel& gripper, const DmgOptions& o,
                      const detail::SurfaceSamples& samples, const detail::SampleGrid& grid,
                      const detail::Patches& patches) {
  formats::Dmg dmg;
  dmg.angle_step_deg = o.angle_step_deg;
  dmg.seed_resolution = o.seed_resolution;
  dmg.normal_threshold = o.normal_threshold;
  dmg.gripper = gripper;
  const int k = dmg.angle_count();

  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) box.extend(mesh.vertices.row(i).transpose());
  const auto facets = detail::find_facets(patches, o.normal_threshold);
  dmg.patch_count = int(patches.size.size());
  dmg.facet_normals = facets.normal;
  dmg.facet_zero_axes = facets.zero_axis;

  const detail::EmbreeMesh embree(mesh);
  const detail::GripperCheck check(embree, box, gripper);
  const double inset = 1e-5 * std::max(box.diagonal().norm(), 0.01);  // start rays just inside the surface
  const double step = o.angle_step_deg * std::numbers::pi / 180;
  const auto opposite =
      opposite_contacts(embree, gripper, grid, patches, samples.spacing, inset, std::cos(o.friction_angle));

  std::vector<std::vector<int>> nodes_of_patch(patches.size.size());
  ProgressReporter report(o.progress, "DMG finger angles");
  report.add_total(opposite.size());
  for (std::size_t i = 0; i < opposite.size(); ++i) {
    report.done();
    if (opposite[i].patch < 0) continue;
    const Eigen::Vector3d& p = patches.position[i];
    const Eigen::Vector3d& n = patches.normal[i];
    const int f = facets.of_patch[i];
    Eigen::Vector3d zero = facets.zero_axis[f] - n.dot(facets.zero_axis[f]) * n;
    zero = zero.norm() > 1e-6 ? Eigen::Vector3d(zero.normalized()) : n.unitOrthogonal();
    const Eigen::Vector3d side = n.cross(zero);
    std::vector<char> valid(k);
    for (int a = 0; a < k; ++a)
      valid[a] = check.free(p, opposite[i].point, n, std::cos(a * step) * zero + std::sin(a * step) * side);
    if (std::none_of(valid.begin(), valid.end(), [](char v) { return v; })) continue;
    for (auto [first, count] : intervals(valid)) {
      formats::DmgNode node;
      node.patch = int(i);
      node.facet = f;
      node.opposite_patch = opposite[i].patch;
      node.first_angle = first;
      node.angle_count = count;
      node.position = p;
      node.normal = n;
      node.zero_axis = zero;
      node.opposite_point = opposite[i].point;
      node.opposite_normal = patches.normal[opposite[i].patch];
      nodes_of_patch[i].push_back(int(dmg.nodes.size()));
      dmg.nodes.push_back(node);
    }
  }
  add_edges(dmg, patches, facets, opposite, nodes_of_patch);
  return dmg;
}

}  // namespace
}  // namespace dmgplace::tools
