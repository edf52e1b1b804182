#include "dmgplace/tools/scan/synthetic_scan.hpp"

#include <cmath>
#include <random>
#include <vector>

#include "../object/embree_mesh.hpp"
#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {

ScanCloud synthetic_scan(const TriMesh& scene, const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                         const SyntheticScanOptions& o) {
  if (!(o.angular_step > 0) || !(o.field_of_view > 0) || !(o.field_of_view < 3) || !(o.noise >= 0))
    throw Error("synthetic scan", "options",
                "angular step and field of view must be positive (field of view < 3 rad), noise >= 0");
  const Eigen::Vector3d forward = (target - eye).normalized();
  if (!forward.allFinite()) throw Error("synthetic scan", "view", "eye and target coincide");
  const Eigen::Vector3d up_hint = std::abs(forward.z()) > 0.99 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d right = forward.cross(up_hint).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  const detail::EmbreeMesh mesh(scene);
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> noise(0.0, o.noise);
  const int half = int(std::floor(0.5 * o.field_of_view / o.angular_step));
  std::vector<Eigen::Vector3d> hits;
  for (int v = -half; v <= half; ++v)
    for (int u = -half; u <= half; ++u) {
      const Eigen::Vector3d dir =
          (forward + std::tan(u * o.angular_step) * right + std::tan(v * o.angular_step) * up).normalized();
      const auto hit = mesh.cast(eye, dir, 1e3);
      if (!hit) continue;
      Eigen::Vector3d p = eye + hit->distance * dir;
      if (o.noise > 0) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      hits.push_back(p);
    }
  if (hits.empty()) throw Error("synthetic scan", "view", "no ray hit the scene");
  ScanCloud scan;
  scan.points.resize(Eigen::Index(hits.size()), 3);
  for (std::size_t i = 0; i < hits.size(); ++i) scan.points.row(Eigen::Index(i)) = hits[i].transpose();
  scan.viewpoint = eye;
  Eigen::Matrix3d r;  // sensor frame: z forward, x right, y down (PCL's camera convention)
  r << right, -up, forward;
  scan.orientation = Eigen::Quaterniond(r);
  return scan;
}

}  // namespace dmgplace::tools
