#include "dmgplace/tools/scan/scan_segmentation.hpp"

#include <pcl/ModelCoefficients.h>
#include <pcl/features/normal_3d.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numeric>

#include "dmgplace/formats/error.hpp"
#include "scan_smoothing.hpp"

namespace dmgplace::tools {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

std::string vec(const Eigen::Vector3d& v) {
  char b[96];
  std::snprintf(b, sizeof b, "(%.3f, %.3f, %.3f)", v.x(), v.y(), v.z());
  return b;
}

Cloud::Ptr subset(const Cloud& c, const std::vector<int>& idx) {
  auto out = std::make_shared<Cloud>();
  out->reserve(idx.size());
  for (int i : idx) out->push_back(c[std::size_t(i)]);
  return out;
}

ScanCluster describe(const Cloud& c, const std::vector<int>& idx) {
  ScanCluster s;
  Eigen::AlignedBox3d box;
  for (int i : idx) {
    const Eigen::Vector3d p = c[std::size_t(i)].getVector3fMap().cast<double>();
    s.centroid += p;
    box.extend(p);
  }
  s.points = idx.size();
  if (!idx.empty()) s.centroid /= double(idx.size()), s.extent = box.sizes();
  return s;
}

// Euclidean clusters of `c` restricted to `idx`, largest first (ties: lowest first index).
std::vector<std::vector<int>> clusters_of(const Cloud& c, const std::vector<int>& idx, const ScanSegmentOptions& o) {
  auto sub = subset(c, idx);
  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  tree->setInputCloud(sub);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(o.cluster_tolerance);
  ec.setMinClusterSize(o.min_cluster_points);
  ec.setMaxClusterSize(int(sub->size()));
  ec.setSearchMethod(tree);
  ec.setInputCloud(sub);
  std::vector<pcl::PointIndices> found;
  ec.extract(found);
  std::vector<std::vector<int>> out;
  for (auto& f : found) {
    std::vector<int> members;
    for (int i : f.indices) members.push_back(idx[std::size_t(i)]);
    std::sort(members.begin(), members.end());
    out.push_back(std::move(members));
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return out;
}

// The scans' points inside the crop box, in one cloud; `scan_of` says which scan saw each.
Cloud gather_points(const std::vector<ScanCloud>& scans, const ScanSegmentOptions& o, std::vector<int>& scan_of,
                    SegmentedObject& out) {
  Cloud all;
  for (std::size_t s = 0; s < scans.size(); ++s)
    for (Eigen::Index i = 0; i < scans[s].points.rows(); ++i) {
      ++out.input_points;
      const Eigen::Vector3d p = scans[s].points.row(i).transpose();
      if (o.crop && !o.crop->contains(p)) continue;
      all.push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
      scan_of.push_back(int(s));
    }
  out.cropped_points = all.size();
  return all;
}

// The dominant plane's points (RANSAC; PCL seeds its generator itself, so this is deterministic),
// empty when it has fewer than a cluster's minimum.
std::vector<int> dominant_plane(const Cloud& all, const ScanSegmentOptions& o) {
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setDistanceThreshold(o.plane_distance);
  seg.setMaxIterations(1000);
  seg.setInputCloud(std::make_shared<Cloud>(all));
  pcl::PointIndices inliers;
  pcl::ModelCoefficients coeff;
  seg.segment(inliers, coeff);
  if (inliers.indices.size() < std::size_t(o.min_cluster_points)) return {};
  std::vector<int> plane = inliers.indices;
  std::sort(plane.begin(), plane.end());
  return plane;
}

// Which of the clusters is the object: --cluster, --cluster-near, or the only one.
int chosen_cluster(const Cloud& all, const std::vector<std::vector<int>>& clusters, const ScanSegmentOptions& o,
                   const SegmentedObject& out, const std::string& file) {
  if (o.cluster >= 0) {
    if (o.cluster >= int(clusters.size()))
      throw Error(file, "--cluster",
                  std::to_string(o.cluster) + " is out of range: " + std::to_string(clusters.size()) + " clusters");
    return o.cluster;
  }
  if (o.cluster_near) {
    int chosen = -1;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < clusters.size(); ++c)
      for (int i : clusters[c]) {
        const double d = (all[std::size_t(i)].getVector3fMap().cast<double>() - *o.cluster_near).squaredNorm();
        if (d < best) best = d, chosen = int(c);
      }
    return chosen;
  }
  if (clusters.size() == 1) return 0;
  std::string list;
  for (std::size_t c = 0; c < clusters.size() && c < 10; ++c)
    list += "\n  " + std::to_string(c) + ": " + std::to_string(out.clusters[c].points) + " points at " +
            vec(out.clusters[c].centroid) + ", " + vec(out.clusters[c].extent) + " m";
  throw Error(file, "clusters",
              std::to_string(clusters.size()) +
                  " clusters: choose one with --cluster N or --cluster-near x,y,z (or --crop ... --whole-crop)" + list);
}

// The object's points in `all`: the support plane taken off when it is one, then the chosen
// Euclidean cluster.
std::vector<int> object_points(const Cloud& all, const ScanSegmentOptions& o, SegmentedObject& out,
                               const std::string& file) {
  std::vector<int> object(all.size());
  std::iota(object.begin(), object.end(), 0);
  std::vector<int> rest = object, plane;
  if (o.support_plane != SupportPlane::Keep) plane = dominant_plane(all, o);
  if (!plane.empty()) {
    std::vector<char> in(all.size(), 0);
    for (int i : plane) in[std::size_t(i)] = 1;
    rest.clear();
    for (std::size_t i = 0; i < all.size(); ++i)
      if (!in[i]) rest.push_back(int(i));
  }
  auto clusters = clusters_of(all, rest, o);
  if (!plane.empty()) {
    // A support plane is wider than what stands on it; a plane no wider than the largest cluster
    // is one of the object's own faces (an object scanned alone): keep it.
    const double plane_width = describe(all, plane).extent.norm();
    const double object_width = clusters.empty() ? 0 : describe(all, clusters.front()).extent.norm();
    const bool support =
        o.support_plane == SupportPlane::Remove || (!clusters.empty() && plane_width > 1.5 * object_width);
    char b[160];
    std::snprintf(b, sizeof b, "plane: %zu points, %.3f m across (largest cluster on it %.3f m): %s", plane.size(),
                  plane_width, object_width,
                  support ? "removed as the support" : "kept, it is no wider than the object");
    out.notes.push_back(b);
    if (support) {
      out.plane_removed = true;
      out.plane_points = plane.size();
    } else {
      clusters = clusters_of(all, object, o);
    }
  }
  for (const auto& c : clusters) out.clusters.push_back(describe(all, c));
  if (clusters.empty())
    throw Error(file, "clusters",
                "no cluster of at least " + std::to_string(o.min_cluster_points) +
                    " points is left (after the crop and the plane)");
  const int chosen = chosen_cluster(all, clusters, o, out, file);
  out.chosen = chosen;
  out.notes.push_back("object: cluster " + std::to_string(chosen) + " of " + std::to_string(clusters.size()) + ", " +
                      std::to_string(clusters[std::size_t(chosen)].size()) + " points at " +
                      vec(out.clusters[std::size_t(chosen)].centroid));
  return clusters[std::size_t(chosen)];
}

// Per object point: where it is (smoothed when asked), its unsigned normal, and the scan that saw it.
struct Surfels {
  std::vector<Eigen::Vector3d> position, normal;
  std::vector<int> seen_by;
};

Surfels estimate_normals(const Cloud::Ptr& cloud, const std::vector<int>& object, const std::vector<int>& scan_of,
                         const ScanSegmentOptions& o) {
  Surfels s;
  if (o.smoothing_radius > 0) {
    std::vector<Eigen::Vector3d> raw;
    for (const auto& p : *cloud) raw.push_back(p.getVector3fMap().cast<double>());
    detail::smooth_points(raw, o.smoothing_radius, s.position, s.normal);
    for (int i : object) s.seen_by.push_back(scan_of[std::size_t(i)]);
    return s;
  }
  pcl::PointCloud<pcl::Normal> normals;
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(cloud);
  ne.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ne.setKSearch(o.normal_neighbours);
  ne.compute(normals);
  for (std::size_t k = 0; k < cloud->size(); ++k) {
    s.position.push_back((*cloud)[k].getVector3fMap().cast<double>());
    s.normal.push_back(Eigen::Vector3d(normals[k].normal_x, normals[k].normal_y, normals[k].normal_z));
    s.seen_by.push_back(scan_of[std::size_t(object[k])]);
  }
  return s;
}

// Each normal turned towards the sensor that saw its point. A viewpoint inside the object's
// bounding box says nothing about sides (a model cloud stored about its own origin): then normals
// point away from the centroid. Points whose fit had too few neighbours are dropped.
void orient_normals(const Cloud& cloud, const Surfels& s, const std::vector<ScanCloud>& scans,
                    const ScanSegmentOptions& o, SegmentedObject& out) {
  Eigen::AlignedBox3d box;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : cloud)
    box.extend(p.getVector3fMap().cast<double>()), centroid += p.getVector3fMap().cast<double>();
  centroid /= double(cloud.size());
  bool viewpoints = true;
  for (const auto& sc : scans) viewpoints = viewpoints && !box.contains(sc.viewpoint);
  out.orientation = viewpoints ? "viewpoint" : "outward";
  if (!viewpoints)
    out.notes.push_back(
        "normals: a scan's viewpoint lies inside the object's box; oriented away from the centroid instead");
  for (std::size_t k = 0; k < s.position.size(); ++k) {
    Eigen::Vector3d n = s.normal[k];
    if (!n.allFinite() || n.norm() < 0.5 || !s.position[k].allFinite()) continue;
    const Eigen::Vector3d& p = s.position[k];
    const Eigen::Vector3d toward =
        viewpoints ? Eigen::Vector3d(scans[std::size_t(s.seen_by[k])].viewpoint - p) : Eigen::Vector3d(p - centroid);
    if (n.dot(toward) < 0) n = -n;
    out.points.push_back(p);
    out.normals.push_back(n.normalized());
  }
  if (viewpoints)
    detail::agree_with_neighbours(out.points, out.normals, std::max(o.smoothing_radius, 2 * o.plane_distance));
}

}  // namespace

SegmentedObject segment_object(const std::vector<ScanCloud>& scans, const ScanSegmentOptions& o,
                               const std::string& file) {
  if (scans.empty()) throw Error(file, "", "no scan given");
  if (!(o.plane_distance > 0) || !(o.cluster_tolerance > 0) || o.min_cluster_points < 1 || o.normal_neighbours < 3 ||
      !(o.smoothing_radius >= 0))
    throw Error(
        file, "segmentation",
        "plane distance and cluster tolerance must be positive, min cluster points >= 1, normal neighbours >= 3");
  SegmentedObject out;
  std::vector<int> scan_of;  // which scan (viewpoint) saw each kept point
  const Cloud all = gather_points(scans, o, scan_of, out);
  if (all.size() < std::size_t(std::max(o.min_cluster_points, o.normal_neighbours)))
    throw Error(file, "--crop",
                "keeps " + std::to_string(all.size()) + " of " + std::to_string(out.input_points) +
                    " points: too few for an object");
  std::vector<int> object(all.size());
  std::iota(object.begin(), object.end(), 0);
  if (o.whole_crop)
    out.notes.push_back("object: the " + std::to_string(all.size()) + " points in the crop box as they are");
  else object = object_points(all, o, out, file);
  const auto cloud = subset(all, object);
  orient_normals(*cloud, estimate_normals(cloud, object, scan_of, o), scans, o, out);
  if (out.points.size() < std::size_t(o.normal_neighbours))
    throw Error(file, "normals", "too few points with a normal");
  return out;
}

}  // namespace dmgplace::tools
