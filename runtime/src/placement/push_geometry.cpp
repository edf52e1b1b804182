#include "dmgplace/runtime/placement/push_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace dmgplace::runtime {

Eigen::Isometry3d ObjectMotion::at(double s) const {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(s * angle, axis).toRotationMatrix();
  m.translation() = pivot - m.linear() * pivot + s * shift;
  return m;
}

Eigen::Vector3d ObjectMotion::velocity(const Eigen::Vector3d& x, double s) const {
  const Eigen::Vector3d r = Eigen::AngleAxisd(s * angle, axis) * (x - pivot);
  return angle * axis.cross(r) + shift;
}

ObjectMotion object_motion(const Eigen::Isometry3d& tcp_world, const Eigen::Isometry3d& grasp_before,
                           const Eigen::Isometry3d& grasp_after) {
  ObjectMotion m;
  m.before = tcp_world * grasp_before.inverse();
  m.after = tcp_world * grasp_after.inverse();
  m.pivot = tcp_world.translation();
  const Eigen::Isometry3d delta = m.after * m.before.inverse();
  const Eigen::AngleAxisd aa(delta.linear());
  m.angle = aa.angle();
  if (m.angle > 1e-12) m.axis = aa.axis();
  // delta(x) = R (x - pivot) + pivot + shift
  m.shift = delta.translation() + delta.linear() * m.pivot - m.pivot;
  return m;
}

namespace {
// Where the ray from `origin` along `dir` leaves the triangle's plane inside it (t > 0), or -1.
double ray_triangle(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const Eigen::Vector3d& a,
                    const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = dir.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-15) return -1;
  const Eigen::Vector3d s = origin - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return -1;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = dir.dot(qv) / det;
  if (v < 0 || u + v > 1) return -1;
  const double t = e2.dot(qv) / det;
  return t > 0 ? t : -1;
}
}  // namespace

std::vector<PushContact> push_contacts(const TriMesh& mesh, const ObjectMotion& motion, int count, double spacing) {
  const Eigen::Isometry3d& pose = motion.before;
  const Eigen::Matrix3d R1 = motion.at(1).linear();
  double lever_max = 0, size = 0;
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    const Eigen::Vector3d x = pose * Eigen::Vector3d(mesh.vertices.row(i).transpose());
    lever_max = std::max(lever_max, motion.velocity(x, 0).norm());
    size = std::max(size, (x - motion.pivot).norm());
  }
  if (!(lever_max > 1e-9)) return {};
  const bool turning = motion.angle * 1e-2 > motion.shift.norm();  // mostly a turn: the lever arm matters
  std::vector<PushContact> all;
  auto consider = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& normal) {
    const Eigen::Vector3d v0 = motion.velocity(x, 0);
    if (v0.norm() < 1e-3 * lever_max) return;
    const Eigen::Vector3d d0 = v0.normalized();
    const double into0 = -normal.dot(d0);
    const Eigen::Vector3d v1 = motion.velocity(x, 1);
    const double into1 = v1.norm() > 0 ? -(R1 * normal).dot(v1.normalized()) : 0;
    if (into0 < std::sqrt(0.5) || into1 < std::sqrt(0.5)) return;
    double shape;
    if (turning) {
      shape = v0.norm() / lever_max;
    } else {  // distance of the line of push from the pivot, against the object's size
      shape = 1 - std::min(1.0, (x - motion.pivot).cross(d0).norm() / std::max(size, 1e-9));
    }
    all.push_back({x, d0, into0 + shape});
  };
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = pose * Eigen::Vector3d(mesh.vertices.row(mesh.triangles(t, 0)).transpose());
    const Eigen::Vector3d b = pose * Eigen::Vector3d(mesh.vertices.row(mesh.triangles(t, 1)).transpose());
    const Eigen::Vector3d c = pose * Eigen::Vector3d(mesh.vertices.row(mesh.triangles(t, 2)).transpose());
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-14) continue;
    const Eigen::Vector3d normal = n.normalized();
    consider((a + b + c) / 3, normal);
    if (!turning && motion.shift.norm() > 0) {
      // The point behind the pivot along the push: pushing there moves the object without turning it.
      const Eigen::Vector3d back = -motion.shift.normalized();
      const double hit = ray_triangle(motion.pivot, back, a, b, c);
      if (hit > 0) consider(motion.pivot + hit * back, normal);
    }
  }
  std::sort(all.begin(), all.end(), [](const PushContact& x, const PushContact& y) { return x.score > y.score; });
  std::vector<PushContact> out;
  for (const auto& c : all) {
    if (int(out.size()) >= count) break;
    bool near = false;
    for (const auto& o : out) near |= (o.point - c.point).norm() < spacing;
    if (!near) out.push_back(c);
  }
  return out;
}

}  // namespace dmgplace::runtime
