#pragma once
// The placement search space S: the union over stable faces f and placement regions r of S(r, f),
// a position on r's support plane and a rotation about its normal. Regions are cropped to the
// query's target volume; supported cells are counted with 2-D prefix sums so the hierarchy can
// tell an empty quadtree cell in O(1).
#include <vector>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"

namespace dmgplace::runtime {

struct CellRange {
  int i0 = 0, i1 = 0, j0 = 0, j1 = 0;  // cells [i0, i1) x [j0, j1)
  int width() const { return i1 - i0; }
  int depth() const { return j1 - j0; }
};

class SearchSpace {
 public:
  SearchSpace(const formats::ObjectArtifact& object, const std::vector<formats::PlacementRegion>& regions,
              const Eigen::AlignedBox3d& volume);

  int face_count() const { return int(faces_->faces.size()); }
  int region_count() const { return int(regions_.size()); }
  const formats::PlacementFace& face(int f) const { return faces_->faces[std::size_t(f)]; }
  const formats::PlacementRegion& region(int r) const { return regions_[std::size_t(r)]; }
  int source_region(int r) const { return source_[std::size_t(r)]; }  // index in the environment artifact

  CellRange full_range(int r) const;
  int supported_cells(int r, const CellRange& c) const;
  bool supported(int r, const Eigen::Vector2d& xy) const;

  // Resting pose of the object: face f down on region r, its COM above `xy`, turned by theta about z.
  Eigen::Isometry3d pose(int f, int r, const Eigen::Vector2d& xy, double theta) const;
  // Stable on r: the face's support polygon (vertices and edge midpoints) and the COM over supported cells.
  bool stable(int f, int r, const Eigen::Isometry3d& pose) const;

 private:
  const formats::PlacementFaces* faces_;
  Eigen::Vector3d com_;
  std::vector<formats::PlacementRegion> regions_;
  std::vector<int> source_;
  std::vector<std::vector<int>> prefix_;  // (width + 1) x (depth + 1) per region
};

}  // namespace dmgplace::runtime
