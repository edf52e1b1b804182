#pragma once
// The grasp the robot actually holds (g0), measured against the object's mesh: how far its TCP is
// from the surface, and how wide the fingers are open around the object. Brute force over the
// triangles: these run once per query.
#include <Eigen/Geometry>
#include <optional>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::runtime {

// Unsigned distance from p to the mesh surface.
double surface_distance(const TriMesh& mesh, const Eigen::Vector3d& p);

// The object's extent along the TCP's closing axis (y) through the TCP: the distance between the
// outermost surface crossings on either side, which is where closed fingers rest. nullopt when
// the line does not cross the surface on both sides of the TCP.
std::optional<double> grasp_width(const TriMesh& mesh, const Eigen::Isometry3d& tcp_in_object);

}  // namespace dmgplace::runtime
