#pragma once
// G(g0): every grasp reachable in-hand from an initial grasp, with its cost and the sequence of
// in-hand actions that gets there (what an executor needs: contact paths, push directions,
// distances, rotation axis and angle).
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "dmgplace/runtime/grasp/grasp_graph.hpp"

namespace dmgplace::runtime {

struct InHandAction {
  GraspMove type = GraspMove::Translation;
  int from_state = 0, to_state = 0;
  // Translation: finger contacts from start to end, one point per DMG node passed.
  std::vector<Eigen::Vector3d> finger1_path, finger2_path;
  double distance = 0;                                       // finger-1 path length (m)
  Eigen::Vector3d push_direction = Eigen::Vector3d::Zero();  // unit, finger 1's first move
  // Rotation: the gripper turns by `angle` (rad, right-handed) about `axis` (the grasp axis,
  // towards finger 1) through `pivot` (the TCP), relative to the object.
  double angle = 0;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
};

struct ReachableGrasp {
  int state = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // TCP in the object frame
  double opening = 0;
  double cost = 0;
};

struct ReachableGrasps {
  int initial_state = -1;              // the snapped initial grasp (-1: the object has no grasps)
  double snap_distance = 0;            // how far the given pose was from it (see GraspGraph::snap)
  std::vector<ReachableGrasp> grasps;  // by increasing cost, the initial grasp first
  ShortestPaths paths;                 // over all states of the graph
  // In-hand actions from the initial grasp to `state` (consecutive moves of one kind merged).
  std::vector<InHandAction> actions_to(const GraspGraph& g, int state) const;
};

// Snaps `initial_tcp` (object frame) to the nearest grasp state and runs Dijkstra from it.
ReachableGrasps reachable_grasps(const GraspGraph& g, const Eigen::Isometry3d& initial_tcp,
                                 std::optional<double> opening = std::nullopt);

}  // namespace dmgplace::runtime
