// Supervoxel patches for the DMG built from scan points (the original's segmentation).
#include <pcl/point_types.h>
#include <pcl/segmentation/supervoxel_clustering.h>

#include <algorithm>
#include <limits>
#include <map>

#include "../scan/scan_smoothing.hpp"
#include "dmg_internal.hpp"
#include "dmgplace/tools/environment/closest_point.hpp"

namespace dmgplace::tools::detail {
namespace {

using Point = pcl::PointXYZRGBA;

constexpr double kVoxelPerSeed = 8.0 / 13.0;  // the original's 8 mm voxels for a 13 mm seed
// PCL seeds one supervoxel per occupied seed-sized octree cell, but cells whose nearest voxel is
// shared collapse into one: a supervoxel covers about 2.5 seed^2 of surface (measured on the scan
// tests' box). The supervoxel seed is scaled so patches cover about seed^2, as the mesh path's do,
// and --seed-resolution means about the same patch size on both paths.
constexpr double kSupervoxelSeedPerSeed = 0.65;
constexpr int kRefinements = 10;  // the original's refinement iterations

Eigen::Vector3d closest_on_mesh(const TriMesh& m, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d out = p;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d q = closest_point_on_triangle(p, m.vertices.row(m.triangles(t, 0)).transpose(),
                                                        m.vertices.row(m.triangles(t, 1)).transpose(),
                                                        m.vertices.row(m.triangles(t, 2)).transpose());
    const double d = (q - p).squaredNorm();
    if (d < best) best = d, out = q;
  }
  return out;
}

}  // namespace

Patches supervoxel_patches(const TriMesh& mesh, const std::vector<Eigen::Vector3d>& points,
                           const std::vector<Eigen::Vector3d>& normals, double seed, SurfaceSamples& samples) {
  auto cloud = std::make_shared<pcl::PointCloud<Point>>();
  auto cloud_normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    Point p;
    p.x = float(points[i].x()), p.y = float(points[i].y()), p.z = float(points[i].z());
    p.rgba = 0;
    cloud->push_back(p);
    cloud_normals->push_back(pcl::Normal(float(normals[i].x()), float(normals[i].y()), float(normals[i].z())));
  }
  const double sv_seed = seed * kSupervoxelSeedPerSeed;
  pcl::SupervoxelClustering<Point> super(float(sv_seed * kVoxelPerSeed), float(sv_seed));
  super.setUseSingleCameraTransform(false);
  super.setInputCloud(cloud);
  super.setNormalCloud(cloud_normals);
  super.setColorImportance(0);
  super.setSpatialImportance(1);
  super.setNormalImportance(1);
  std::map<std::uint32_t, pcl::Supervoxel<Point>::Ptr> voxels;
  super.extract(voxels);
  super.refineSupervoxels(kRefinements, voxels);
  std::multimap<std::uint32_t, std::uint32_t> adjacency;
  super.getSupervoxelAdjacency(adjacency);
  const auto labels = super.getLabeledCloud();  // one label per input point, 0 = none

  Patches p;
  // Patches in label order, only supervoxels that hold some input point (facets weigh by points).
  std::map<std::uint32_t, int> patch_of_label;
  for (std::size_t i = 0; i < points.size() && i < labels->size(); ++i)
    if (voxels.contains((*labels)[i].label)) patch_of_label.emplace((*labels)[i].label, 0);
  {
    int next = 0;
    for (auto& [label, k] : patch_of_label) k = next++;
  }
  const std::size_t n = patch_of_label.size();
  p.position.assign(n, Eigen::Vector3d::Zero());
  p.normal.assign(n, Eigen::Vector3d::Zero());
  p.size.assign(n, 0);
  p.neighbours.assign(n, {});
  std::vector<Eigen::Vector3d> centroid(n, Eigen::Vector3d::Zero());
  samples = {};
  for (std::size_t i = 0; i < points.size() && i < labels->size(); ++i) {
    const auto it = patch_of_label.find((*labels)[i].label);
    if (it == patch_of_label.end()) continue;
    const int k = it->second;
    samples.position.push_back(points[i]);
    samples.normal.push_back(normals[i]);
    samples.triangle.push_back(-1);
    p.of_sample.push_back(k);
    p.normal[std::size_t(k)] += normals[i];
    centroid[std::size_t(k)] += points[i];
    ++p.size[std::size_t(k)];
  }
  // Sample spacing: twice the median gap between neighbouring points, at least seed / 5 as for meshes.
  samples.spacing = std::max(seed / 5, 2 * median_point_spacing(points));

  std::vector<double> best(n, std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < n; ++k)
    if (p.size[k] > 0) centroid[k] /= double(p.size[k]);
  for (std::size_t s = 0; s < samples.position.size(); ++s) {
    const std::size_t k = std::size_t(p.of_sample[s]);
    const double d = (samples.position[s] - centroid[k]).squaredNorm();
    if (d < best[k]) best[k] = d, p.position[k] = samples.position[s];
  }
  for (std::size_t k = 0; k < n; ++k) {
    p.position[k] = closest_on_mesh(mesh, p.position[k]);
    p.normal[k] = p.normal[k].norm() > 1e-9 ? Eigen::Vector3d(p.normal[k].normalized()) : Eigen::Vector3d::UnitZ();
  }
  for (const auto& [a, b] : adjacency) {
    const auto ia = patch_of_label.find(a), ib = patch_of_label.find(b);
    if (ia == patch_of_label.end() || ib == patch_of_label.end() || ia->second == ib->second) continue;
    p.neighbours[std::size_t(ia->second)].push_back(ib->second);
    p.neighbours[std::size_t(ib->second)].push_back(ia->second);
  }
  for (auto& nb : p.neighbours) {
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }
  return p;
}

}  // namespace dmgplace::tools::detail
