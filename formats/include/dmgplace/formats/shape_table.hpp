#pragma once
// Stores a list of collision shapes (primitives and meshes) as flat tables under one group;
// shared by the environment and robot artifacts.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/h5_writer.hpp"

namespace dmgplace::formats {

struct OwnedShape {
  int owner = -1;  // index of the link or scene object the shape belongs to
  Shape shape;
};

void write_shapes(H5Writer& w, const std::string& group, const std::vector<OwnedShape>& shapes);
std::vector<OwnedShape> read_shapes(const H5Reader& r, const std::string& group);
// Semantic problems (sizes, poses, mesh ranges, owners in [0, owner_count)).
std::vector<std::string> check_shapes(const std::vector<OwnedShape>& shapes, int owner_count, const std::string& where);
// Why `hull` is not a closed, outward surface over mesh vertices with every vertex inside it.
std::optional<std::string> hull_problem(const TriMesh& mesh, const RowMatrixX3i& hull);

// Pose <-> [x y z qx qy qz qw].
void pose_to_array(const Eigen::Isometry3d& pose, double* out7);
// Throws dmgplace::Error naming file and element unless the quaternion has unit length.
Eigen::Isometry3d pose_from_array(const double* in7, const std::string& file, const std::string& element);

}  // namespace dmgplace::formats
