#pragma once
// A conservative sphere cover of a held object for the fast collision layer: the object's
// bounding box cut into cubes, one sphere (the cube's circumscribed sphere) per cube that touches
// the surface or lies inside, so the union contains the whole solid.
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::runtime {

struct SphereSet {
  std::vector<Eigen::Vector3d> centers;  // object frame
  std::vector<double> radii;
};

// `cells_per_axis` cubes along the longest extent (>= 1). Empty meshes: dmgplace::Error.
SphereSet cover_object(const TriMesh& mesh, int cells_per_axis = 8);

// Ray-parity inside test against a closed mesh (majority over three axis rays).
bool inside_mesh(const TriMesh& mesh, const Eigen::Vector3d& p);

}  // namespace dmgplace::runtime
