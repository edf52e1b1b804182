#include "analytic_sdf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "dmgplace/runtime/collision/primitive_obstacles.hpp"

namespace dmgplace::test {

// The runtime's exact primitive distance (itself tested against FCL: PrimitiveObstacles test).
double primitive_signed_distance(const Shape& s, const Eigen::Vector3d& world) {
  if (s.type == ShapeType::Mesh) throw std::invalid_argument("analytic_sdf: meshes are not supported");
  return runtime::shape_signed_distance(s, world);
}

double scene_signed_distance(const Scene& scene, const Eigen::Vector3d& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& o : scene.objects)
    for (const auto& s : o.shapes) d = std::min(d, primitive_signed_distance(s, p));
  return d;
}

std::shared_ptr<runtime::Grid3> analytic_sdf(const Scene& scene, const Eigen::AlignedBox3d& box, double res,
                                             double band) {
  std::array<int, 3> dims;
  for (int a = 0; a < 3; ++a) dims[std::size_t(a)] = int(std::ceil(box.sizes()[a] / res)) + 1;
  auto g = std::make_shared<runtime::Grid3>(box.min(), res, dims);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        g->values()[g->index(i, j, k)] = float(std::min(band, scene_signed_distance(scene, g->point(i, j, k))));
  return g;
}

}  // namespace dmgplace::test
