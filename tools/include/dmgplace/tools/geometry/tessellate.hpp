#pragma once
// Triangle meshes of collision shapes, in the shape's parent frame (origin applied): the common
// currency of distance fields, sampling and exact checks.
#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

// Box: 12 triangles. Cylinder and sphere: `segments` around (>= 8); a circumscribed polygon so the
// mesh contains the true primitive. Mesh: its triangles. Outward orientation throughout.
TriMesh tessellate(const Shape& shape, int segments = 24);
// All shapes of a scene in the world frame, concatenated.
TriMesh tessellate(const Scene& scene, int segments = 24);
void append_mesh(TriMesh& into, const TriMesh& more);

}  // namespace dmgplace::tools
