#pragma once
// Plain value types shared by tools, artifacts and the runtime. World frame is z-up, metres.
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace dmgplace::formats {

// Robots and rooms are metres across: a shape or coordinate beyond a kilometre is a unit error or
// a crafted file, and the distance fields and sphere covers built from it would not fit in
// memory. Every reader and artifact check refuses it.
inline constexpr double kMaxGeometryExtent = 1000;

using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

struct TriMesh {
  RowMatrixX3d vertices;   // metres
  RowMatrixX3i triangles;  // counter-clockwise seen from outside
  bool empty() const { return vertices.rows() == 0 || triangles.rows() == 0; }
};

enum class ShapeType : int { Box = 0, Cylinder = 1, Sphere = 2, Mesh = 3 };

// A collision shape placed by `origin` in its parent frame (link frame or world).
struct Shape {
  ShapeType type = ShapeType::Box;
  // Box: full extents x, y, z. Cylinder: radius, length (along local z), 0. Sphere: radius, 0, 0.
  // Mesh: scale x, y, z (already applied to `mesh`; kept for the record).
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  TriMesh mesh;  // only for ShapeType::Mesh
  // Mesh: its convex hull as triangles over mesh.vertices (outward, counter-clockwise seen from
  // outside); empty where not computed. The exact layer measures gaps against it: a lower bound
  // of the mesh's own gap, at GJK's cost instead of a mesh hierarchy's.
  RowMatrixX3i hull;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
};

// One named rigid obstacle of a scene, its shapes in world coordinates.
struct SceneObject {
  std::string name;
  std::vector<Shape> shapes;
};

struct Scene {
  std::vector<SceneObject> objects;
  RowMatrixX3d points;  // scan points in the world frame (empty for geometric scenes)
};

}  // namespace dmgplace::formats

// The runtime and tools use the geometry types unqualified, from namespace dmgplace.
namespace dmgplace {
using formats::kMaxGeometryExtent;
using formats::RowMatrixX3d;
using formats::RowMatrixX3i;
using formats::Scene;
using formats::SceneObject;
using formats::Shape;
using formats::ShapeType;
using formats::TriMesh;
}  // namespace dmgplace
