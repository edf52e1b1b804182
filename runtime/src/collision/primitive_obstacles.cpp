#include "dmgplace/runtime/collision/primitive_obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dmgplace/formats/triangle_distance.hpp"
#include "dmgplace/formats/winding_number.hpp"

namespace dmgplace::runtime {

namespace {
// `half`: box half extents; cylinder (radius, -, half length) about z; sphere (radius, -, -).
double local_signed_distance(ShapeType type, const Eigen::Vector3d& half, const Eigen::Vector3d& p) {
  switch (type) {
    case ShapeType::Box: {
      const Eigen::Vector3d d = p.cwiseAbs() - half;
      return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    }
    case ShapeType::Cylinder: {
      const Eigen::Vector2d d(std::hypot(p.x(), p.y()) - half.x(), std::abs(p.z()) - half.z());
      return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    }
    case ShapeType::Sphere:
      return p.norm() - half.x();
    case ShapeType::Mesh:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

Eigen::Vector3d half_extents(const Shape& s) {
  switch (s.type) {
    case ShapeType::Box:
      return 0.5 * s.size;
    case ShapeType::Cylinder:
      return Eigen::Vector3d(s.size[0], 0, 0.5 * s.size[1]);  // FCL: axis z, centered
    case ShapeType::Sphere:
      return Eigen::Vector3d::Constant(s.size[0]);
    case ShapeType::Mesh:
      break;
  }
  return Eigen::Vector3d::Zero();
}
}  // namespace

PrimitiveObstacles::LanePrimitive PrimitiveObstacles::to_lanes(const Primitive& p) {
  LanePrimitive f{};
  f.type = p.type;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) std::fill_n(f.to_local[3 * r + c], lanes::WF, float(p.to_local(r, c)));
    std::fill_n(f.origin[r], lanes::WF, float(p.origin[r]));
    f.half[r] = float(p.half[r]);
  }
  f.bound_radius = std::nextafter(float(p.bound_radius), std::numeric_limits<float>::infinity());
  // Exactly upright only: the products left out are then exact zeros (and dz times one).
  const Eigen::Matrix3d& R = p.to_local;
  f.upright = R(0, 2) == 0 && R(1, 2) == 0 && R(2, 0) == 0 && R(2, 1) == 0 && R(2, 2) == 1;
  return f;
}

std::shared_ptr<const PrimitiveObstacles> PrimitiveObstacles::from_scene(const Scene& scene) {
  if (scene.points.rows() > 0) return nullptr;
  auto out = std::make_shared<PrimitiveObstacles>();
  for (const auto& o : scene.objects)
    for (const auto& s : o.shapes) {
      Primitive p;
      p.type = s.type;
      p.to_local = s.origin.linear().transpose();
      p.origin = s.origin.translation();
      if (s.type == ShapeType::Mesh) return nullptr;
      p.half = half_extents(s);
      p.bound_radius = s.type == ShapeType::Box        ? p.half.norm()
                       : s.type == ShapeType::Cylinder ? std::hypot(p.half.x(), p.half.z())
                                                       : p.half.x();
      out->prims_.push_back(p);
      out->lanes_.push_back(to_lanes(p));
      out->extent_ = std::max(out->extent_, p.origin.cwiseAbs().maxCoeff() + p.bound_radius);
    }
  out->build_blocks();
  return out;
}

double shape_signed_distance(const Shape& s, const Eigen::Vector3d& p) {
  return local_signed_distance(s.type, half_extents(s), s.origin.inverse() * p);
}

double inner_radius(const std::vector<Shape>& shapes, const Eigen::Vector3d& p) {
  double best = 0;
  for (const auto& s : shapes) {
    if (s.type != ShapeType::Mesh) {
      best = std::max(best, -shape_signed_distance(s, p));
      continue;
    }
    const Eigen::Vector3d local = s.origin.inverse() * p;
    if (s.mesh.empty() || winding_number(s.mesh, local) < 0.5) continue;
    double d2 = std::numeric_limits<double>::infinity();
    for (Eigen::Index t = 0; t < s.mesh.triangles.rows(); ++t) {
      const Eigen::Vector3d a = s.mesh.vertices.row(s.mesh.triangles(t, 0)).transpose();
      const Eigen::Vector3d b = s.mesh.vertices.row(s.mesh.triangles(t, 1)).transpose();
      const Eigen::Vector3d c = s.mesh.vertices.row(s.mesh.triangles(t, 2)).transpose();
      d2 = std::min(d2, (formats::closest_point_on_triangle(local, a, b, c) - local).squaredNorm());
    }
    best = std::max(best, std::sqrt(d2));
  }
  return best;
}

double PrimitiveObstacles::local_distance(const Primitive& s, const Eigen::Vector3d& world) {
  return local_signed_distance(s.type, s.half, s.to_local * (world - s.origin));
}

void PrimitiveObstacles::reaching(const Eigen::Vector3d& p, double within, std::vector<int>& out) const {
  out.clear();
  for (std::size_t k = 0; k < prims_.size(); ++k) {
    const double reach = within + prims_[k].bound_radius;
    if (reach > 0 && (p - prims_[k].origin).squaredNorm() < reach * reach) out.push_back(int(k));
  }
}

bool PrimitiveObstacles::separations(const Eigen::Vector3d& p, double within, const std::vector<int>& candidates,
                                     std::vector<Separation>& out) const {
  out.clear();
  for (const int k : candidates) {
    const Primitive& s = prims_[std::size_t(k)];
    const double reach = within + s.bound_radius;
    if (reach <= 0 || (p - s.origin).squaredNorm() >= reach * reach) continue;
    const Eigen::Vector3d local = s.to_local * (p - s.origin);
    Eigen::Vector3d nearest;  // the primitive's point nearest p, local
    switch (s.type) {
      case ShapeType::Box:
        nearest = local.cwiseMax(-s.half).cwiseMin(s.half);
        break;
      case ShapeType::Cylinder: {
        const double r = std::hypot(local.x(), local.y());
        const double scale = r > s.half.x() ? s.half.x() / r : 1.0;
        nearest = Eigen::Vector3d(local.x() * scale, local.y() * scale, std::clamp(local.z(), -s.half.z(), s.half.z()));
        break;
      }
      default: {  // a sphere (from_scene stores nothing else)
        const double r = local.norm();
        nearest = r > s.half.x() ? Eigen::Vector3d(local * (s.half.x() / r)) : local;
        break;
      }
    }
    const Eigen::Vector3d away = local - nearest;
    const double d = away.norm();
    if (!(d > 1e-12)) return false;  // inside or on it
    if (d >= within) continue;
    out.push_back({d, s.to_local.transpose() * (away / d)});
  }
  return true;
}

std::uint64_t PrimitiveObstacles::touching(const Eigen::Vector3d& p, double radius) const {
  std::uint64_t mask = 0;
  const std::size_t n = std::min<std::size_t>(prims_.size(), 64);
  for (std::size_t k = 0; k < n; ++k) {
    const Primitive& s = prims_[k];
    const double reach = radius + s.bound_radius;
    if (reach <= 0 || (p - s.origin).squaredNorm() >= reach * reach) continue;
    if (local_distance(s, p) < radius) mask |= std::uint64_t(1) << k;
  }
  return mask;
}

}  // namespace dmgplace::runtime
