#pragma once
// The per-kind halves of deep_validate (deep_validation.hpp): each appends its checks.
#include <cmath>
#include <random>
#include <string>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/tools/validate/deep_validation.hpp"

namespace dmgplace::tools::detail {

void deep_environment(const formats::EnvironmentArtifact& a, const DeepOptions& o, DeepReport& report);
void deep_robot(const formats::RobotArtifact& a, const DeepOptions& o, DeepReport& report);
void deep_object(const formats::ObjectArtifact& a, const DeepOptions& o, DeepReport& report);
// --check-inputs for a robot: joint limits against the URDF (and joint_limits.yaml) the header names.
void robot_against_inputs(const formats::RobotArtifact& a, const std::filesystem::path& file, DeepReport& report);
// --check-inputs for an object baked from a mesh file: the mesh read again, the mass asked for.
void object_against_inputs(const formats::ObjectArtifact& a, const std::filesystem::path& file, DeepReport& report);

// Keeps the largest disagreement of a check as samples arrive (from one thread). `describe()`
// (the sample's text) is called only for a new worst.
struct WorstOf {
  double worst = 0;
  std::string sample;
  template <class Describe>
  void add(double disagreement, Describe describe) {
    if (std::isnan(worst)) return;  // a NaN disagreement stays the worst
    if (!(disagreement <= worst)) worst = disagreement, sample = describe();
  }
};

std::string fmt(double v);
std::string fmt(const Eigen::Vector3d& p);

}  // namespace dmgplace::tools::detail
