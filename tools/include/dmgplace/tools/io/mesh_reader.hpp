#pragma once
// Reads a triangle mesh file (STL ascii/binary, OBJ, PLY, DAE, ... through assimp) into a clean TriMesh.
#include <filesystem>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/tools/io/mesh_check.hpp"

namespace dmgplace::tools {

struct MeshReadOptions {
  double scale = 1.0;  // uniform factor to metres (0.001 for files in millimetres)
  bool repair = true;  // re-orient inconsistent or inside-out faces (see clean_mesh)
  // Per-axis factor applied after `scale` (URDF <mesh scale="x y z">); a mirror keeps faces outward.
  Eigen::Vector3d axis_scale = Eigen::Vector3d::Ones();
};

// All meshes of the file merged with their node transforms applied, scaled, then clean_mesh.
// Missing or unreadable file, no triangles, bad scale or a rejected mesh: dmgplace::Error.
// `report` (optional) receives clean_mesh's report.
TriMesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options = {}, MeshReport* report = nullptr);

}  // namespace dmgplace::tools
