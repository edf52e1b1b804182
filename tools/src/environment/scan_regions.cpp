#include "dmgplace/tools/environment/scan_regions.hpp"

#include <pcl/ModelCoefficients.h>
#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <cmath>
#include <limits>

namespace dmgplace::tools {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

constexpr int kMaxPlanes = 8;
constexpr double kVolumeSlack = 1e-3;

Cloud::Ptr to_cloud(const RowMatrixX3d& pts, const Eigen::AlignedBox3d& keep) {
  auto c = std::make_shared<Cloud>();
  for (Eigen::Index i = 0; i < pts.rows(); ++i) {
    const Eigen::Vector3d p = pts.row(i).transpose();
    if (keep.contains(p)) c->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  }
  return c;
}

Cloud::Ptr voxel(const Cloud::Ptr& in, double leaf) {
  auto out = std::make_shared<Cloud>();
  pcl::VoxelGrid<pcl::PointXYZ> vg;
  vg.setInputCloud(in);
  vg.setLeafSize(float(leaf), float(leaf), float(leaf));
  vg.filter(*out);
  return out;
}

// Cells touched by a plane's inliers, with single-cell holes (scan gaps) closed.
std::vector<char> plane_cells(const Cloud& inliers, const CellGrid& g) {
  const std::size_t n = std::size_t(g.nx) * std::size_t(g.ny);
  std::vector<char> hit(n, 0);
  for (const auto& p : inliers) {
    const int i = int(std::floor((p.x - g.origin.x()) / g.resolution));
    const int j = int(std::floor((p.y - g.origin.y()) / g.resolution));
    if (i >= 0 && i < g.nx && j >= 0 && j < g.ny) hit[std::size_t(i) + std::size_t(g.nx) * std::size_t(j)] = 1;
  }
  auto morph = [&](const std::vector<char>& src, bool dilate) {
    std::vector<char> dst(n, 0);
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        bool any = false, all = true;
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di) {
            const int a = i + di, b = j + dj;
            const bool v =
                a >= 0 && a < g.nx && b >= 0 && b < g.ny && src[std::size_t(a) + std::size_t(g.nx) * std::size_t(b)];
            any |= v;
            all &= v;
          }
        dst[std::size_t(i) + std::size_t(g.nx) * std::size_t(j)] = dilate ? any : all;
      }
    return dst;
  };
  auto closed = morph(morph(hit, true), false);
  for (std::size_t k = 0; k < n; ++k) closed[k] = closed[k] || hit[k];  // erosion never removes seen cells
  return closed;
}

}  // namespace

RowMatrixX3d voxel_filter(const RowMatrixX3d& points, double leaf) {
  if (!(leaf > 0) || points.rows() == 0) return points;
  const Eigen::AlignedBox3d all(Eigen::Vector3d::Constant(-std::numeric_limits<double>::max()),
                                Eigen::Vector3d::Constant(std::numeric_limits<double>::max()));
  auto out = voxel(to_cloud(points, all), leaf);
  RowMatrixX3d m(Eigen::Index(out->size()), 3);
  for (std::size_t i = 0; i < out->size(); ++i) m.row(Eigen::Index(i)) << (*out)[i].x, (*out)[i].y, (*out)[i].z;
  return m;
}

std::vector<SurfaceSample> scan_surface_samples(const RowMatrixX3d& points, const Eigen::AlignedBox3d& volume,
                                                const CellGrid& g, const RegionOptions& o) {
  std::vector<SurfaceSample> out;
  if (g.nx <= 0 || g.ny <= 0) return out;
  // Noise a stereo or depth scan puts on a flat surface; points closer than this to a plane are on it.
  const double plane_tol = std::max(0.01, o.resolution);
  const double clutter_tol = std::min(plane_tol, 0.5 * o.min_free_height);
  Eigen::AlignedBox3d keep = volume;
  keep.min().z() -= plane_tol;
  auto cloud = voxel(to_cloud(points, keep), 0.5 * o.resolution);
  if (cloud->size() < 10) return out;

  pcl::PointCloud<pcl::Normal> normals;
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(cloud);
  ne.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ne.setRadiusSearch(std::max(3 * o.resolution, 0.02));
  ne.compute(normals);
  const double cos_tilt = std::cos(o.max_tilt_deg * M_PI / 180.0);
  auto horizontal = std::make_shared<Cloud>();
  for (std::size_t k = 0; k < cloud->size(); ++k)
    if (std::isfinite(normals[k].normal_z) && std::abs(normals[k].normal_z) >= cos_tilt)
      horizontal->push_back((*cloud)[k]);

  const std::size_t min_points =
      std::max<std::size_t>(30, std::size_t(o.min_area / (0.25 * o.resolution * o.resolution) / 4));
  for (int plane = 0; plane < kMaxPlanes && horizontal->size() >= min_points; ++plane) {
    pcl::SACSegmentation<pcl::PointXYZ> seg;
    seg.setOptimizeCoefficients(true);
    seg.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
    seg.setAxis(Eigen::Vector3f::UnitZ());
    seg.setEpsAngle(o.max_tilt_deg * M_PI / 180.0);
    seg.setMethodType(pcl::SAC_RANSAC);
    seg.setDistanceThreshold(plane_tol);
    seg.setMaxIterations(500);
    seg.setInputCloud(horizontal);
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coeff;
    seg.segment(inliers, coeff);
    if (inliers.indices.size() < min_points || coeff.values.size() != 4) break;
    const double a = coeff.values[0], b = coeff.values[1], c = coeff.values[2], d = coeff.values[3];
    std::vector<char> is_inlier(horizontal->size(), 0);
    Cloud in, rest;
    for (int k : inliers.indices) is_inlier[std::size_t(k)] = 1;
    for (std::size_t k = 0; k < horizontal->size(); ++k) (is_inlier[k] ? in : rest).push_back((*horizontal)[k]);
    *horizontal = std::move(rest);
    if (std::abs(c) < cos_tilt) continue;
    auto plane_z = [&](const Eigen::Vector2d& xy) { return -(a * xy.x() + b * xy.y() + d) / c; };

    const auto cells = plane_cells(in, g);
    // Free height: the lowest scan point standing above each cell (clutter), else up to V's top.
    std::vector<float> free(cells.size(), std::numeric_limits<float>::infinity());
    for (const auto& p : *cloud) {
      const int i = int(std::floor((p.x - g.origin.x()) / g.resolution));
      const int j = int(std::floor((p.y - g.origin.y()) / g.resolution));
      if (i < 0 || i >= g.nx || j < 0 || j >= g.ny) continue;
      const std::size_t k = std::size_t(i) + std::size_t(g.nx) * std::size_t(j);
      if (!cells[k]) continue;
      const double dz = p.z - plane_z(Eigen::Vector2d(p.x, p.y));
      if (dz > clutter_tol) free[k] = std::min(free[k], float(dz));
    }
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const std::size_t k = std::size_t(i) + std::size_t(g.nx) * std::size_t(j);
        if (!cells[k]) continue;
        const double z = plane_z(g.center(i, j));
        if (z < volume.min().z() - kVolumeSlack || z > volume.max().z()) continue;
        const double f = std::min(double(free[k]), volume.max().z() - z);
        if (f >= o.min_free_height) out.push_back({i, j, z, float(f)});
      }
  }
  return out;
}

}  // namespace dmgplace::tools
