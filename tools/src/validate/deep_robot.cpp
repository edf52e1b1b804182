// validate --deep for ROBOT.h5: every link's collision geometry inside its spheres, and every
// self-distance table at or below the exact distance of its pair.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/validate/deep_checks.hpp"

namespace dmgplace::tools::detail {
namespace {

// The cover's proofs need every surface point inside a sphere; this only absorbs rounding.
constexpr double kCoverTolerance = 1e-6;
// Table values are rounded down from FCL's distances; this absorbs FCL's own tolerance.
constexpr double kTableTolerance = 1e-5;

// Points on a shape's surface in its link's frame: a mesh's vertices, a box's corners, points on a
// sphere and on a cylinder's two rims (where a cover of a primitive is tightest).
std::vector<Eigen::Vector3d> surface_points(const Shape& s) {
  std::vector<Eigen::Vector3d> local;
  constexpr int kRound = 64;
  switch (s.type) {
    case ShapeType::Mesh:
      for (Eigen::Index v = 0; v < s.mesh.vertices.rows(); ++v) local.push_back(s.mesh.vertices.row(v).transpose());
      break;
    case ShapeType::Box:
      for (int c = 0; c < 8; ++c)
        local.push_back(0.5 * s.size.cwiseProduct(Eigen::Vector3d(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1)));
      break;
    case ShapeType::Cylinder:
      for (int k = 0; k < kRound; ++k) {
        const double t = 2 * std::numbers::pi * k / kRound;
        for (double z : {-0.5, 0.5})
          local.emplace_back(s.size.x() * std::cos(t), s.size.x() * std::sin(t), z * s.size.y());
      }
      break;
    case ShapeType::Sphere:
      for (int k = 0; k < kRound * 4; ++k) {  // a Fibonacci lattice
        const double z = 1 - (2.0 * k + 1) / (kRound * 4), r = std::sqrt(1 - z * z),
                     t = k * std::numbers::pi * (3 - std::sqrt(5.0));
        local.push_back(s.size.x() * Eigen::Vector3d(r * std::cos(t), r * std::sin(t), z));
      }
      break;
  }
  for (auto& p : local) p = s.origin * p;
  return local;
}

DeepCheck sphere_coverage(const formats::RobotArtifact& a) {
  WorstOf w;
  w.worst = -std::numeric_limits<double>::infinity();  // a sound cover reports its margin (negative)
  int samples = 0;
  for (std::size_t l = 0; l < a.model.links.size(); ++l)
    for (const auto& shape : a.model.links[l].collision)
      for (const auto& p : surface_points(shape)) {
        double out = std::numeric_limits<double>::infinity();  // outside the nearest sphere by
        for (const auto& s : a.spheres)
          if (s.link == int(l)) out = std::min(out, (p - s.center).norm() - s.radius);
        ++samples;
        w.add(out, [&] {
          return "link '" + a.model.links[l].name + "' surface point " + fmt(p) + " (link frame): " + fmt(out) +
                 " m outside its nearest sphere";
        });
      }
  return {"link collision geometry inside the link's spheres",
          "links/spheres",
          samples,
          w.worst,
          kCoverTolerance,
          "m",
          w.sample};
}

DeepCheck table_below_exact(const formats::RobotArtifact& a, const formats::SelfDistanceTable& t, std::size_t index,
                            const runtime::Kinematics& kin, const runtime::ExactChecker& exact, const DeepOptions& o,
                            std::mt19937_64& rng) {
  const auto& links = a.model.links;
  const std::string pair = "'" + links[std::size_t(t.link_a)].name + "' / '" + links[std::size_t(t.link_b)].name + "'";
  WorstOf w;
  Eigen::VectorXd q(kin.dof());
  for (int s = 0; s < o.samples; ++s) {
    for (int k = 0; k < kin.dof(); ++k)
      q[k] = std::uniform_real_distribution<double>(kin.lower()[k], kin.upper()[k])(rng);
    const double x0 = kin.joint_value(t.joints[0], q), x1 = t.joints[1] >= 0 ? kin.joint_value(t.joints[1], q) : 0.0;
    const double bound = t.lower_bound(x0, x1), d = exact.link_distance(q, t.link_a, t.link_b);
    w.add(bound - d, [&] {
      std::string at = "q =";
      for (int k = 0; k < kin.dof(); ++k) at += " " + fmt(q[k]);
      return "table " + std::to_string(index) + " (" + pair + ") at " + at + ": bound " + fmt(bound) + " m, exact " +
             fmt(d) + " m";
    });
  }
  return {"self-distance table " + std::to_string(index) + " (" + pair + ") at or below the exact distance",
          "self_tables/distance",
          o.samples,
          w.worst,
          kTableTolerance,
          "m",
          w.sample};
}

}  // namespace

void deep_robot(const formats::RobotArtifact& a, const DeepOptions& o, DeepReport& report) {
  report.checks.push_back(sphere_coverage(a));
  if (a.self_tables.empty()) return;
  const runtime::Kinematics kin(a.model, a.model.arm_base, a.model.arm_tip);
  const runtime::ExactChecker exact(kin, Scene{});
  std::mt19937_64 rng(o.seed);
  for (std::size_t i = 0; i < a.self_tables.size(); ++i)
    report.checks.push_back(table_below_exact(a, a.self_tables[i], i, kin, exact, o, rng));
}

}  // namespace dmgplace::tools::detail
