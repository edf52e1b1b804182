#include "dmgplace/runtime/collision/fcl_geometry.hpp"

#include <fcl/fcl.h>

#include <vector>

namespace dmgplace::runtime {
namespace {
template <typename BV>
std::shared_ptr<fcl::CollisionGeometryd> mesh_hierarchy(const TriMesh& m) {
  auto model = std::make_shared<fcl::BVHModel<BV>>();
  std::vector<fcl::Vector3d> v(std::size_t(m.vertices.rows()));
  std::vector<fcl::Triangle> t(std::size_t(m.triangles.rows()));
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = m.vertices.row(Eigen::Index(i)).transpose();
  for (std::size_t i = 0; i < t.size(); ++i)
    t[i] = fcl::Triangle(std::size_t(m.triangles(Eigen::Index(i), 0)), std::size_t(m.triangles(Eigen::Index(i), 1)),
                         std::size_t(m.triangles(Eigen::Index(i), 2)));
  model->beginModel();
  model->addSubModel(v, t);
  model->endModel();
  model->computeLocalAABB();
  return model;
}
}  // namespace

std::shared_ptr<fcl::CollisionGeometryd> fcl_mesh(const TriMesh& mesh, FclMeshNodes nodes) {
  return nodes == FclMeshNodes::Obbrss ? mesh_hierarchy<fcl::OBBRSSd>(mesh) : mesh_hierarchy<fcl::OBBd>(mesh);
}

std::shared_ptr<fcl::CollisionGeometryd> fcl_geometry(const Shape& s, FclMeshNodes mesh_nodes) {
  std::shared_ptr<fcl::CollisionGeometryd> g;
  switch (s.type) {
    case ShapeType::Box:
      g = std::make_shared<fcl::Boxd>(s.size.x(), s.size.y(), s.size.z());
      break;
    case ShapeType::Cylinder:
      g = std::make_shared<fcl::Cylinderd>(s.size[0], s.size[1]);
      break;
    case ShapeType::Sphere:
      g = std::make_shared<fcl::Sphered>(s.size[0]);
      break;
    case ShapeType::Mesh:
      return fcl_mesh(s.mesh, mesh_nodes);
  }
  g->computeLocalAABB();
  return g;
}

}  // namespace dmgplace::runtime
