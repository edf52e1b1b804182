#pragma once
// From depth scans (PCD) to an object's surface: read every scan with its viewpoint, segment the
// object (scan_segmentation), reconstruct a closed surface (surface_reconstruction) and move it
// to an object frame centered on its bounding box (axes kept: the scan frame's).
#include <Eigen/Geometry>
#include <filesystem>
#include <vector>

#include "dmgplace/tools/scan/scan_segmentation.hpp"
#include "dmgplace/tools/scan/surface_reconstruction.hpp"

namespace dmgplace::tools {

struct ScanObjectOptions {
  double scale = 1.0;  // to metres (0.001 for scans in millimetres)
  ScanSegmentOptions segment;
  ReconstructOptions reconstruct;
};

struct ScanObject {
  TriMesh mesh;                                              // object frame
  std::vector<Eigen::Vector3d> points, normals;              // the segmented scan points, object frame
  Eigen::Vector3d origin_in_scan = Eigen::Vector3d::Zero();  // object frame origin in the scan frame
  SegmentedObject segmented;                                 // in the scan frame
  ReconstructionReport reconstruction;
};

ScanObject object_from_scans(const std::vector<std::filesystem::path>& scans, const ScanObjectOptions& options);

}  // namespace dmgplace::tools
