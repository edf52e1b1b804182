#include "dmgplace/runtime/placement/objective.hpp"

#include <cmath>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::runtime {

Objective::Objective(std::vector<ObjectiveTerm> terms, const EnvironmentModel& env,
                     const formats::ObjectArtifact& object, std::vector<Eigen::Vector3d> points)
    : terms_(std::move(terms)), env_(&env), com_(object.mass.com), points_(std::move(points)) {
  if (terms_.empty()) throw Error("query", "objective", "no objective term");
  for (auto& t : terms_) {
    if (!std::isfinite(t.weight) || !t.vector.allFinite())
      throw Error("query", std::string("objective ") + to_string(t.kind), "weight and vector must be finite");
    if (t.kind == ObjectiveTerm::Kind::Clearance && (!env.clearance || points_.empty()))
      throw Error("query", "objective clearance", "needs the environment's clearance field and the object's points");
    if (t.kind == ObjectiveTerm::Kind::Depth || t.kind == ObjectiveTerm::Kind::Upright) {
      if (t.vector.norm() < 1e-9)
        throw Error("query", std::string("objective ") + to_string(t.kind), "needs a non-zero direction");
      t.vector.normalize();
    }
  }
}

double Objective::clearance(const Eigen::Isometry3d& pose) const {
  double sum = 0;
  for (const auto& p : points_) sum += env_->clearance->sample(pose * p);
  return sum / double(points_.size());
}

double Objective::value(const Eigen::Isometry3d& pose) const {
  const Eigen::Vector3d com = pose * com_;
  double v = 0;
  for (const auto& t : terms_) {
    switch (t.kind) {
      case ObjectiveTerm::Kind::Clearance:
        v += t.weight * clearance(pose);
        break;
      case ObjectiveTerm::Kind::Depth:
        v += t.weight * com.dot(t.vector);
        break;
      case ObjectiveTerm::Kind::Distance:
        v -= t.weight * (com - t.vector).norm();
        break;
      case ObjectiveTerm::Kind::Upright:
        v += t.weight * (pose.linear() * t.vector).z();
        break;
    }
  }
  return v;
}

Eigen::Isometry3d Objective::moved(const Eigen::Isometry3d& pose, const Eigen::Vector3d& d) const {
  const Eigen::Vector3d com = pose * com_;
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(d.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  turn.translation() = com - turn.linear() * com + Eigen::Vector3d(d.x(), d.y(), 0);
  return turn * pose;
}

Eigen::Vector3d Objective::gradient(const Eigen::Isometry3d& pose) const {
  const Eigen::Vector3d h(1e-3, 1e-3, 5e-3);
  Eigen::Vector3d g;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(i) * h[i];
    g[i] = (value(moved(pose, e)) - value(moved(pose, -e))) / (2 * h[i]);
  }
  return g;
}

}  // namespace dmgplace::runtime
