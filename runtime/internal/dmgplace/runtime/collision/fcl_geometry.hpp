#pragma once
// One shape's FCL geometry: a box, cylinder or sphere primitive, or a triangle mesh's bounding
// volume hierarchy. The exact layer builds its links and scene with it, and so does bench-mbm's
// stock baseline (tools/bench). FCL's type is only declared here, so this header pulls in no FCL
// header.
#include <memory>

#include "dmgplace/formats/geometry_types.hpp"

namespace fcl {
template <typename S>
class CollisionGeometry;
}

namespace dmgplace::runtime {

// Node type of a mesh's hierarchy. OBB: FCL has a closed-form OBB for a box, cylinder or sphere
// obstacle (the exact layer's collision queries). OBBRSS: distance queries need its RSS half;
// MoveIt builds every mesh so.
enum class FclMeshNodes { Obb, Obbrss };

// The geometry with its local AABB computed.
std::shared_ptr<fcl::CollisionGeometry<double>> fcl_geometry(const Shape& shape, FclMeshNodes mesh_nodes);
std::shared_ptr<fcl::CollisionGeometry<double>> fcl_mesh(const TriMesh& mesh, FclMeshNodes nodes);

}  // namespace dmgplace::runtime
