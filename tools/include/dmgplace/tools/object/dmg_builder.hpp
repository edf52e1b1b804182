#pragma once
// The Dexterous Manipulation Graph of an object (Cruciani et al., IROS 2018) for a parallel-jaw
// gripper: surface patches, facets of agreeing normals, valid finger angles per patch checked
// exactly against the mesh (Embree), opposite contacts and sliding edges. See docs/dmg.md.
#include <string>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/tools/system/progress.hpp"

namespace dmgplace::tools {

struct DmgOptions {
  double seed_resolution = 0.01;   // m: patch size (a cubic cell of this edge length)
  double angle_step_deg = 10;      // finger angle step; must divide 360
  double normal_threshold = 0.07;  // adjacent patches join a facet when |n_i - n_j|^2 < this
  double crease_angle = 0.6;       // rad: mesh edges sharper than this bound patches
  double friction_angle = 0.5;     // rad: the opposite contact's normal must be this close to antipodal
  ProgressFn progress;             // patches whose finger angles are checked
};

// Throws dmgplace::Error naming `file` for bad options (angle step not dividing 360, sizes not
// positive) or an unusable mesh.
formats::Dmg build_dmg(const TriMesh& mesh, const formats::GripperModel& gripper, const DmgOptions& options,
                       const std::string& file);

// The same graph with the original's patches: supervoxels of scan points (outward unit normals)
// instead of cells of the mesh; fingers, opposite contacts and angles are checked against `mesh`,
// the surface reconstructed from those points.
formats::Dmg build_dmg_from_points(const TriMesh& mesh, const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<Eigen::Vector3d>& normals, const formats::GripperModel& gripper,
                                   const DmgOptions& options, const std::string& file);

}  // namespace dmgplace::tools
