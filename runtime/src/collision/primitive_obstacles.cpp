#include "dmgplace/runtime/collision/primitive_obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dmgplace::runtime {

std::shared_ptr<const PrimitiveObstacles> PrimitiveObstacles::from_scene(const Scene& scene) {
  if (scene.points.rows() > 0) return nullptr;
  auto out = std::make_shared<PrimitiveObstacles>();
  for (const auto& o : scene.objects)
    for (const auto& s : o.shapes) {
      Primitive p;
      p.type = s.type;
      p.to_local = s.origin.linear().transpose();
      p.origin = s.origin.translation();
      switch (s.type) {
        case ShapeType::Box:
          p.half = 0.5 * s.size;
          p.bound_radius = p.half.norm();
          break;
        case ShapeType::Cylinder:  // FCL's convention: axis z, centred
          p.half = Eigen::Vector3d(s.size[0], 0, 0.5 * s.size[1]);
          p.bound_radius = std::hypot(p.half.x(), p.half.z());
          break;
        case ShapeType::Sphere:
          p.half = Eigen::Vector3d::Constant(s.size[0]);
          p.bound_radius = s.size[0];
          break;
        case ShapeType::Mesh:
          return nullptr;
      }
      out->prims_.push_back(p);
    }
  return out;
}

double PrimitiveObstacles::local_distance(const Primitive& s, const Eigen::Vector3d& world) {
  const Eigen::Vector3d p = s.to_local * (world - s.origin);
  switch (s.type) {
    case ShapeType::Box: {
      const Eigen::Vector3d d = p.cwiseAbs() - s.half;
      return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    }
    case ShapeType::Cylinder: {
      const Eigen::Vector2d d(std::hypot(p.x(), p.y()) - s.half.x(), std::abs(p.z()) - s.half.z());
      return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    }
    case ShapeType::Sphere:
      return p.norm() - s.half.x();
    case ShapeType::Mesh:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

double PrimitiveObstacles::distance(const Eigen::Vector3d& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : prims_) {
    // The bounding sphere gives a lower bound: skip shapes that cannot beat the best so far.
    if ((p - s.origin).norm() - s.bound_radius >= best) continue;
    best = std::min(best, local_distance(s, p));
  }
  return best;
}

std::uint64_t PrimitiveObstacles::touching(const Eigen::Vector3d& p, double radius) const {
  std::uint64_t mask = 0;
  const std::size_t n = std::min<std::size_t>(prims_.size(), 64);
  for (std::size_t k = 0; k < n; ++k) {
    const Primitive& s = prims_[k];
    if ((p - s.origin).norm() - s.bound_radius >= radius) continue;
    if (local_distance(s, p) < radius) mask |= std::uint64_t(1) << k;
  }
  return mask;
}

}  // namespace dmgplace::runtime
