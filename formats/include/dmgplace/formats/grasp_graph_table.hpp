#pragma once
// The grasp graph of an object as stored in OBJECT.h5 (group `grasp_graph`, its own schema
// version): baked once from the DMG so the runtime only reads it.
// A grasp state is (DMG node, finger angle index): finger 1 on the node's contact, finger 2 on its
// opposite contact, the gripper turned by angle x step about the grasp axis. States are stored node
// by node, each node's interval in order. Moves: rotation to the neighbouring angle of the same
// node (cost = step x rotation_weight) and translation along a DMG edge keeping the angle (cost =
// distance between the finger-1 contacts). Both are reversible, so every edge has its reverse.
#include <cstdint>
#include <string>
#include <vector>

namespace dmgplace::formats {

struct Dmg;

inline constexpr int kGraspGraphSchemaVersion = 1;

enum class GraspMoveKind : std::uint8_t { Translation = 0, Rotation = 1 };

struct GraspGraphTable {
  double rotation_weight = 0.1;           // cost per radian of in-hand rotation (the original's)
  std::vector<std::int32_t> state_node;   // per state
  std::vector<std::int32_t> state_angle;  // per state: absolute angle index in [0, angle_count)
  // Compressed adjacency: edges leaving state s are [offsets[s], offsets[s + 1]).
  std::vector<std::int32_t> offsets{0};
  std::vector<std::int32_t> targets;
  std::vector<double> costs;
  std::vector<GraspMoveKind> moves;
  // The snap index: per state the TCP pose in the object frame (x y z qx qy qz qw; y = grasp axis
  // towards finger 1, z = approach) and the opening between the contacts, so snapping a held grasp
  // onto the graph needs no trigonometry.
  std::vector<double> tcp;
  std::vector<double> opening;

  int size() const { return int(state_node.size()); }
  std::size_t edge_count() const { return targets.size(); }
};

// Derives the table from a DMG (the offline bake; save_object fills an empty table this way).
GraspGraphTable build_grasp_graph_table(const Dmg& dmg, double rotation_weight = 0.1);

// Every way the table disagrees with the DMG, one line each: states that do not enumerate the
// nodes' intervals, edges that join neither adjacent angles of a node nor the same angle of
// DMG-adjacent nodes, costs that are not positive or differ from the move's cost, edges without a
// reverse of equal cost, a snap index off the states' poses, edges the DMG implies but the table
// lacks. Assumes the DMG itself passed its checks.
std::vector<std::string> check_grasp_graph_table(const Dmg& dmg, const GraspGraphTable& t);

}  // namespace dmgplace::formats
