#pragma once
// Segments one object out of depth scans (PCL): crop box, the dominant support plane removed
// (RANSAC), Euclidean clusters, one cluster chosen; normals estimated on it and turned towards the
// sensor that saw each point (the PCD header's VIEWPOINT); the points smoothed by moving least
// squares.
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "dmgplace/tools/io/pcd_reader.hpp"

namespace dmgplace::tools {

enum class SupportPlane { Auto, Remove, Keep };

struct ScanSegmentOptions {
  std::optional<Eigen::AlignedBox3d> crop;          // keep only points inside (cloud frame)
  bool whole_crop = false;                          // take the cropped points as the object: no plane, no clusters
  SupportPlane support_plane = SupportPlane::Auto;  // Auto: removed when wider than the object on it
  double plane_distance = 0.005;                    // m: RANSAC inlier distance of the plane
  double cluster_tolerance = 0.01;                  // m: Euclidean clustering gap
  int min_cluster_points = 50;
  int cluster = -1;                             // >= 0: that cluster (largest first)
  std::optional<Eigen::Vector3d> cluster_near;  // the cluster with the point nearest this
  int normal_neighbours = 20;                   // k of the normal estimation (no smoothing)
  // Moving least squares: each point projected onto a quadric fitted within this radius, which
  // also gives its normal; takes sensor noise out of hulls and Poisson surfaces. 0: off.
  double smoothing_radius = 0.01;
};

struct ScanCluster {
  std::size_t points = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();  // bounding-box size
};

struct SegmentedObject {
  std::vector<Eigen::Vector3d> points, normals;  // the object; unit normals facing outward
  std::size_t input_points = 0, cropped_points = 0, plane_points = 0;
  bool plane_removed = false;
  std::vector<ScanCluster> clusters;  // largest first
  int chosen = -1;
  std::string orientation;         // "viewpoint" (towards each point's sensor) or "outward" (from the centroid)
  std::vector<std::string> notes;  // what was decided, one line each
};

// Throws dmgplace::Error naming `file` when nothing is left, or several clusters remain and none
// was chosen (the message lists them with sizes and centroids).
SegmentedObject segment_object(const std::vector<ScanCloud>& scans, const ScanSegmentOptions& options,
                               const std::string& file);

}  // namespace dmgplace::tools
