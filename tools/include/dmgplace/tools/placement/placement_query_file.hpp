#pragma once
// QUERY.yaml for `dmgplace place`: which artifacts, where the arm starts, how the object is held,
// where it should go and what to maximise. Layout (paths relative to the query file):
//
//   robot: artifacts/dmgarm.h5
//   object: artifacts/bottle.h5
//   environment: artifacts/cabinet.h5
//   start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]        # arm joints, or {joint_name: value}
//   initial_grasp: {pose: [x, y, z, qx, qy, qz, qw], opening: 0.06}   # TCP in the object frame
//   volume: [xmin, ymin, zmin, xmax, ymax, zmax]          # optional: the environment's V
//   objective:                                            # optional: clearance, weight 1
//     - {term: clearance, weight: 1}
//     - {term: depth, weight: 1, direction: [1, 0, 0]}    # also: distance (target), upright (axis)
//   time_limit: 10                                        # seconds
//   seed: 1
//   variant: full                                         # full | random-grasp | no-regrasp
//   options: {threads: 0, goal_iterations: 25, ...}       # PlacementOptions by name
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "dmgplace/runtime/placement/placement_query.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::tools {

struct PlacementQueryFile {
  std::filesystem::path path;
  std::filesystem::path robot, object, environment;  // resolved against the query's folder
  std::vector<double> start_list;                    // either a list in chain order...
  std::map<std::string, double> start_named;         // ... or joint name -> value
  double time_limit = 10;
  runtime::PlacementQuery query;  // q0 filled by resolve_start()
};

// Relative artifact paths are resolved against `artifact_dir`, or the query's folder when empty.
// A path that leads outside that folder (`..`, an absolute path, a symbolic link) is refused
// unless `allow_outside`. Unknown or duplicate keys and out-of-range values are refused with the
// key, its line and the range.
PlacementQueryFile read_placement_query(const std::filesystem::path& path,
                                        const std::filesystem::path& artifact_dir = {}, bool allow_outside = false);
// `text` resolved against `root`; throws (naming file and element) when it escapes root, unless allowed.
std::filesystem::path resolve_artifact_path(const std::string& text, const std::filesystem::path& root,
                                            bool allow_outside, const std::string& file, const std::string& element);
// The named start entries for joints outside the robot's arm chain (another arm, a torso): pass
// them to the PlacementWorld, which sets and checks them. A name that is no joint of the robot is
// refused here, naming the query file.
std::map<std::string, double> world_joint_values(const PlacementQueryFile& f, const RobotModel& robot);
// The start configuration in the arm chain's joint order; errors name the query file. Named
// entries outside the chain must hold in `kin` (a world built with world_joint_values).
Eigen::VectorXd resolve_start(const PlacementQueryFile& f, const runtime::Kinematics& kin);

}  // namespace dmgplace::tools
