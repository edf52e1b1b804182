#pragma once
// Faces a rigid object can rest on: convex-hull facets merged by normal, kept when stable.
#include <string>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/object_artifact.hpp"

namespace dmgplace::tools {

// Options of the placement-face analysis (not the planner's runtime::PlacementOptions).
struct FaceOptions {
  double merge_angle = 0.2;  // rad: a face grows from its seed facet over neighbours within this of the seed's normal
  double margin = 0.01;      // m: COM projection at least this far inside the support polygon...
  double margin_fraction = 0.1;  // ...but at most this fraction of the object's smallest width (small objects)
};

// `com` is the (possibly overridden) center of mass. Throws dmgplace::Error naming `file` when the
// mesh has no 3-D convex hull (flat or degenerate) or an option is out of range.
formats::PlacementFaces compute_placement_faces(const TriMesh& mesh, const Eigen::Vector3d& com,
                                                const FaceOptions& options, const std::string& file);

}  // namespace dmgplace::tools
