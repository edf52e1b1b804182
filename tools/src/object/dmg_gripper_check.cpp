#include "dmg_gripper_check.hpp"

#include <cmath>

namespace dmgplace::tools::detail {
namespace {

constexpr double kPalmPiece = 0.04;  // m: palm pieces no larger than this along any axis

// The box's world-axis bounds (conservative prefilter against the object's bounds).
Eigen::AlignedBox3d bounds(const OrientedBox& b) {
  const Eigen::Vector3d r = b.axes.cwiseAbs() * b.half;
  return {b.center - r, b.center + r};
}

}  // namespace

GripperCheck::GripperCheck(const EmbreeMesh& mesh, const Eigen::AlignedBox3d& object_box,
                           const formats::GripperModel& g)
    : mesh_(mesh), object_box_(object_box), g_(g) {
  int cuts[3];
  for (int i = 0; i < 3; ++i) cuts[i] = std::max(1, int(std::ceil(g.palm_size[i] / kPalmPiece)));
  const Eigen::Vector3d piece(g.palm_size.x() / cuts[0], g.palm_size.y() / cuts[1], g.palm_size.z() / cuts[2]);
  for (int i = 0; i < cuts[0]; ++i)
    for (int j = 0; j < cuts[1]; ++j)
      for (int k = 0; k < cuts[2]; ++k) {
        const Eigen::Vector3d c =
            g.palm_center - 0.5 * g.palm_size + piece.cwiseProduct(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5));
        palm_parts_.push_back({c, Eigen::Matrix3d::Identity(), 0.5 * piece});
      }
}

bool GripperCheck::box_free(const OrientedBox& b) const {
  return !bounds(b).intersects(object_box_) || !mesh_.overlaps(b);
}

bool GripperCheck::free(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                        const Eigen::Vector3d& approach) const {
  Eigen::Matrix3d r;
  r.col(1) = n;
  r.col(2) = approach;
  r.col(0) = n.cross(approach);
  const Eigen::Vector3d tcp = 0.5 * (p + q);
  const double pad = 0.5 * (p - q).norm() + g_.contact_tolerance;
  const Eigen::Vector3d half(0.5 * g_.finger_width, 0.5 * g_.finger_thickness, 0.5 * g_.finger_length);
  const double z = g_.tip_offset - 0.5 * g_.finger_length;
  for (double side : {1.0, -1.0}) {
    const Eigen::Vector3d local(0, side * (pad + half.y()), z);
    if (!box_free({tcp + r * local, r, half})) return false;
  }
  // The fingers are free and overlap the palm, so the gripper is outside the object unless a palm
  // piece meets the surface (no piece can lie wholly inside: the pieces are connected to the fingers).
  const OrientedBox palm{tcp + r * g_.palm_center, r, 0.5 * g_.palm_size};
  if (!bounds(palm).intersects(object_box_)) return true;
  for (const auto& part : palm_parts_)
    if (!box_free({tcp + r * part.center, r, part.half})) return false;
  return true;
}

}  // namespace dmgplace::tools::detail
