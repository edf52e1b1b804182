#pragma once
// ROBOT.h5: the kinematic tree, collision geometry, planning chain and allowed collision pairs.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/robot_model.hpp"

namespace dmgplace::formats {

inline constexpr const char* kRobotSchema = "dmgplace.robot";
inline constexpr int kRobotSchemaVersion =
    5;  // 3: self-distance tables; 4: convex hulls of mesh shapes; 5: acceleration limits

// One sphere of the fast collision model, in its link's frame.
struct LinkSphere {
  int link = -1;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0;
};

// Exact distance between the collision geometry of two links whose relative pose depends on one or
// two revolute chain joints, tabulated over those joints' ranges (bake-robot). The fast layer reads
// a lower bound off it where the pair's spheres overlap (the Panda's wrist: link5 / link7 sit 1-2
// cm apart over most of joint 6's range, closer than any small sphere cover can prove).
//   lower bound at q = distance[nearest node] - sum_k slope[k] * |q_k - node_k|
// slope[k] bounds how fast the distance can change with joint k (metres per radian): the largest
// distance from joint k's axis of any point on the link that joint moves relative to the other.
struct SelfDistanceTable {
  int link_a = -1, link_b = -1;
  std::array<int, 2> joints{-1, -1};  // model joint indices; joints[1] = -1 for a 1-D table
  std::array<double, 2> lower{0, 0}, step{1, 1}, slope{0, 0};
  std::array<int, 2> count{1, 1};  // nodes per joint (count[1] = 1 for a 1-D table)
  std::vector<float> distance;     // count[0] x count[1], row-major; rounded down, 0 on contact

  // The proven lower bound at joint values x0 (joints[0]) and x1 (joints[1]; ignored for 1-D).
  double lower_bound(double x0, double x1) const {
    const double x[2] = {x0, x1};
    std::size_t index = 0;
    double loss = 0;
    for (std::size_t k = 0; k < 2; ++k) {
      // Nearest node, clamped to the grid (no libm call: this runs in every fast check).
      const double u = (x[k] - lower[k]) / step[k];
      const long i = !(u > 0) ? 0 : std::min(long(std::min(u, 1e9) + 0.5), long(count[k]) - 1);  // NaN to 0
      loss += slope[k] * std::abs(x[k] - (lower[k] + double(i) * step[k]));
      index = index * std::size_t(count[k]) + std::size_t(i);
    }
    return double(distance[index]) - loss;
  }
};

struct RobotArtifact {
  ArtifactHeader header;
  RobotModel model;
  std::vector<LinkSphere> spheres;  // union contains every link's collision geometry
  std::vector<SelfDistanceTable> self_tables;
};

void save_robot(RobotArtifact artifact, const std::filesystem::path& path);
// Reads the file and refuses it unless check_robot finds nothing (see load_object).
RobotArtifact load_robot(const std::filesystem::path& path);
// Reads without the semantic checks: for `validate` and tests (see read_object_unchecked).
RobotArtifact read_robot_unchecked(const std::filesystem::path& path);
std::vector<std::string> check_robot(const RobotArtifact& a);
Summary summarize_robot(const RobotArtifact& a);

}  // namespace dmgplace::formats
