#pragma once
// Stages of the DMG builder (private to dmgplace_tools).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools::detail {

// Dense, deterministic surface sampling: `position[i]` lies on triangle `triangle[i]`.
struct SurfaceSamples {
  double spacing = 0;
  std::vector<Eigen::Vector3d> position, normal;
  std::vector<int> triangle;
};
SurfaceSamples sample_surface(const TriMesh& mesh, double spacing);

// Groups of triangles bounded by creases (dihedral angle above `crease_angle`).
std::vector<int> crease_regions(const TriMesh& mesh, double crease_angle);

// A hash grid over sample positions for neighbour searches.
class SampleGrid {
 public:
  SampleGrid(const std::vector<Eigen::Vector3d>& points, double cell);
  // Calls f(index) for every point within `radius` (<= cell) of p.
  template <class F>
  void near(const Eigen::Vector3d& p, double radius, F&& f) const;
  // Nearest point within `max_radius` of p, or -1.
  int nearest(const Eigen::Vector3d& p, double max_radius) const;

 private:
  std::array<long, 3> key(const Eigen::Vector3d& p) const;
  long hash(const std::array<long, 3>& k) const;
  const std::vector<Eigen::Vector3d>& points_;
  double cell_;
  std::vector<int> start_, order_;  // bucketed point indices (counting sort by hash)
};

struct Patches {
  std::vector<int> of_sample;                // patch of each sample
  std::vector<Eigen::Vector3d> position;     // a sample near the patch center: on the surface
  std::vector<Eigen::Vector3d> normal;       // unit mean sample normal
  std::vector<int> size;                     // samples
  std::vector<std::vector<int>> neighbours;  // adjacent patches, sorted
};
// Cells of `seed` edge length intersected with crease regions; patches under `min_fraction` of a
// full cell's samples join their most similar neighbour.
Patches segment_patches(const TriMesh& mesh, const SurfaceSamples& s, const SampleGrid& grid, double seed,
                        double crease_angle);

// The original DMG's segmentation (Cruciani et al.): PCL supervoxels of scan points (voxel =
// seed x 8/13, the original's 8 mm for 13 mm; colour ignored, space and normals equally weighted).
// `samples` receives the labelled points (spacing: their median gap, at least seed / 5); a patch's
// position is its point nearest the supervoxel centroid, moved onto `mesh` (the reconstructed
// surface the fingers are checked against); its normal the mean of its points' normals.
Patches supervoxel_patches(const TriMesh& mesh, const std::vector<Eigen::Vector3d>& points,
                           const std::vector<Eigen::Vector3d>& normals, double seed, SurfaceSamples& samples);

struct Facets {
  std::vector<int> of_patch;
  std::vector<Eigen::Vector3d> normal, zero_axis;
};
Facets find_facets(const Patches& p, double normal_threshold);

template <class F>
void SampleGrid::near(const Eigen::Vector3d& p, double radius, F&& f) const {
  const auto k = key(p);
  for (long dx = -1; dx <= 1; ++dx)
    for (long dy = -1; dy <= 1; ++dy)
      for (long dz = -1; dz <= 1; ++dz) {
        const long h = hash({k[0] + dx, k[1] + dy, k[2] + dz});
        for (int i = start_[h]; i < start_[h + 1]; ++i) {
          const int j = order_[i];
          if ((points_[j] - p).squaredNorm() <= radius * radius) f(j);
        }
      }
}

}  // namespace dmgplace::tools::detail
