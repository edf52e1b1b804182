#pragma once
// The grasp graph of an object, read as baked into OBJECT.h5 (formats/grasp_graph_table.hpp holds
// its definition); the runtime only indexes it. A grasp state is (DMG node, finger angle index).
// The bake already checked the whole gripper (both fingers and palm) at every angle of a node's
// interval, so every state is collision-free with the object.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
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
  // The object's stored graph (load_object has checked it against the DMG).
  explicit GraspGraph(const formats::ObjectArtifact& object);
  GraspGraph(formats::Dmg dmg, const formats::GraspGraphTable& table);

  int size() const { return int(states_.size()); }
  const GraspState& state(int s) const { return states_[s]; }
  const formats::Dmg& dmg() const { return dmg_; }
  const WeightedGraph& graph() const { return graph_; }
  GraspMove move(int edge) const { return moves_[edge]; }  // edge index as in graph()
  double angle_step() const { return step_; }              // rad
  // State of (node, angle), or -1 when the angle is not in the node's interval.
  int find(int node, int angle) const;

  // Gripper TCP frame in the object frame: y = grasp axis (towards finger 1), z = approach.
  Eigen::Isometry3d tcp_pose(int s) const;  // from the stored snap index
  double opening(int s) const { return opening_[s]; }
  const Eigen::Vector3d& contact1(int s) const { return dmg_.nodes[states_[s].node].position; }
  const Eigen::Vector3d& contact2(int s) const { return dmg_.nodes[states_[s].node].opposite_point; }

  // The state whose TCP pose is nearest `tcp` (metres + snap_weight x rotation angle, the gripper's
  // 180-degree symmetry about z counted as the same pose, plus |opening difference| if an opening is given).
  // Returns -1 for an empty graph; `distance` (optional) receives the score.
  int snap(const Eigen::Isometry3d& tcp, std::optional<double> opening = std::nullopt,
           double* distance = nullptr) const;
  static constexpr double snap_weight = 0.05;  // m per rad

 private:
  formats::Dmg dmg_;
  double step_ = 0;
  std::vector<GraspState> states_;
  std::vector<int> first_state_;  // per node
  WeightedGraph graph_;
  std::vector<GraspMove> moves_;
  std::vector<Eigen::Isometry3d> tcp_;
  std::vector<double> opening_;
};

}  // namespace dmgplace::runtime
