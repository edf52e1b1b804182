#pragma once
// The grasp graph of an object, derived at load time from its DMG (no CGAL / PCL / Embree).
// A grasp state is (DMG node, finger angle index): finger 1 on the node's contact, finger 2 on its
// opposite contact, the gripper turned by angle * step about the grasp axis. The bake already
// checked the whole gripper (both fingers and palm) at every angle of a node's interval, so every
// state is collision-free with the object.
// Moves: rotation to the neighbouring angle of the same node (cost = step x rotation_weight), and
// translation along a DMG edge keeping the angle (cost = distance between finger-1 contacts).
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/runtime/grasp/shortest_paths.hpp"

namespace dmgplace::runtime {

struct GraspState {
  int node = 0;
  int angle = 0;  // absolute angle index in [0, angle_count)
};

enum class GraspMove : std::uint8_t { Translation, Rotation };

class GraspGraph {
 public:
  // rotation_weight: cost per radian of in-hand rotation (the original used 0.1).
  explicit GraspGraph(const formats::Dmg& dmg, double rotation_weight = 0.1);

  int size() const { return int(states_.size()); }
  const GraspState& state(int s) const { return states_[s]; }
  const formats::Dmg& dmg() const { return dmg_; }
  const WeightedGraph& graph() const { return graph_; }
  GraspMove move(int edge) const { return moves_[edge]; }  // edge index as in graph()
  double angle_step() const { return step_; }               // rad
  // State of (node, angle), or -1 when the angle is not in the node's interval.
  int find(int node, int angle) const;

  // Gripper TCP frame in the object frame: y = grasp axis (towards finger 1), z = approach.
  Eigen::Isometry3d tcp_pose(int s) const;
  double opening(int s) const;
  const Eigen::Vector3d& contact1(int s) const { return dmg_.nodes[states_[s].node].position; }
  const Eigen::Vector3d& contact2(int s) const { return dmg_.nodes[states_[s].node].opposite_point; }

  // The state whose TCP pose is nearest `tcp` (metres + snap_weight x rotation angle, the gripper's
  // 180-degree symmetry about z counted as the same pose, plus |opening difference| if opening >= 0).
  // Returns -1 for an empty graph; `distance` (optional) receives the score.
  int snap(const Eigen::Isometry3d& tcp, double opening = -1, double* distance = nullptr) const;
  static constexpr double snap_weight = 0.05;  // m per rad

 private:
  formats::Dmg dmg_;
  double step_ = 0;
  std::vector<GraspState> states_;
  std::vector<int> first_state_;  // per node
  WeightedGraph graph_;
  std::vector<GraspMove> moves_;
};

}  // namespace dmgplace::runtime
