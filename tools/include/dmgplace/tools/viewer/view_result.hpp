#pragma once
// What the viewer needs from a `dmgplace place` result.json (layout: tools/src/placement/placement_report.cpp).
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>
#include <map>
#include <vector>

#include "dmgplace/runtime/motion/trajectory.hpp"

namespace dmgplace::tools::viewer {

struct InHandStep {
  std::string type;  // "push" or "rotate"
  double distance = 0, angle = 0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::Zero(), pivot = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> finger1, finger2;  // contact paths, object frame
};

struct Improvement {
  double time = 0, objective = 0;
};

struct ViewResult {
  std::filesystem::path file;  // the result.json read
  std::filesystem::path robot, object, environment;
  std::string query_file, variant;
  std::vector<std::string> joint_names;
  Eigen::VectorXd start;
  Eigen::Isometry3d initial_grasp = Eigen::Isometry3d::Identity();  // TCP in the object frame
  std::optional<Eigen::AlignedBox3d> volume;
  bool solved = false;
  std::string reason;
  double seconds = 0;
  // The best solution, when solved.
  double time = 0, objective = 0;
  int region = -1;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();   // object resting pose, world
  Eigen::Isometry3d grasp = Eigen::Isometry3d::Identity();  // TCP in the object frame
  double opening = 0;
  double release_opening = 0;  // how far the fingers open to let go; 0: not in the result (older ones)
  std::vector<InHandStep> in_hand;
  std::vector<Eigen::VectorXd> path, retreat;
  // Their timed trajectories (trajectory.json beside result.json); empty where the result has none.
  runtime::Trajectory path_timing, retreat_timing;
  // The world's joints outside the arm chain (a query's named start: another arm's park pose).
  std::map<std::string, double> joint_values;
  // The pusher arm's in-hand actions (a query with a pusher): its chain tip, its joints, and per
  // action its path, the waypoints in contact and the object's poses before and after.
  struct Push {
    std::vector<Eigen::VectorXd> path;
    runtime::Trajectory timing;  // the path timed; empty where the result has none
    int begin = 0, end = 0;
    Eigen::Isometry3d object_before = Eigen::Isometry3d::Identity(), object_after = Eigen::Isometry3d::Identity();
  };
  std::string pusher_tip;
  std::vector<std::string> pusher_joint_names;
  std::vector<Push> pushes;
  std::vector<Improvement> improvements;
};

// Reads RESULT_DIR/result.json and, when present, RESULT_DIR/trajectory.json; with `artifacts` non-empty, the artifact files are looked up in that
// folder by file name instead. Throws dmgplace::Error naming the file (and the JSON element).
ViewResult read_view_result(const std::filesystem::path& result_dir, const std::filesystem::path& artifacts = {});

}  // namespace dmgplace::tools::viewer
