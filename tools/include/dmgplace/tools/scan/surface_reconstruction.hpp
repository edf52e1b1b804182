#pragma once
// A closed surface from an object's scan points (with outward normals): screened Poisson
// (pcl::Poisson) for any shape seen well enough, or the convex hull (CGAL) for convex objects seen
// from few sides. Reports how much of the result lies near a scan point: the rest is invented.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/tools/io/mesh_check.hpp"

namespace dmgplace::tools {

enum class Reconstruction { Poisson, Hull };

struct ReconstructOptions {
  Reconstruction method = Reconstruction::Poisson;
  int poisson_depth = 7;                // octree depth: cells of (object size x 1.1) / 2^depth
  double poisson_samples_per_node = 3;  // higher smooths noisier scans
  double seen_distance = 0;             // m: a surface point this near a scan point was seen; 0: 3 x point spacing
  double invented_warning = 0.5;        // warn when less than this fraction of the surface was seen
};

struct ReconstructionReport {
  double seen_fraction = 0;  // of the surface area, within seen_distance of a scan point
  double seen_distance = 0;  // m, as used
  double point_spacing = 0;  // m: median distance of a scan point to its nearest neighbour
  MeshReport mesh;           // clean_mesh's report on the result
  std::vector<std::string> warnings;
};

// The surface in the points' frame, cleaned (clean_mesh), vertices and faces in a canonical order
// so the same points always give the same mesh. dmgplace::Error naming `file` when the method
// yields no closed surface.
TriMesh reconstruct_surface(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                            const ReconstructOptions& options, const std::string& file, ReconstructionReport& report);

// Fraction of the mesh's area within `distance` of some point (area-uniform surface samples).
double seen_fraction(const TriMesh& mesh, const std::vector<Eigen::Vector3d>& points, double distance);

}  // namespace dmgplace::tools
