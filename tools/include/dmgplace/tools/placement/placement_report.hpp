#pragma once
// What `dmgplace place` writes to its output folder: result.json (query, best solution and every
// improvement), trace.csv (time, best objective, counters), path.csv (joint waypoints of the
// best solution's arm path, then its retreat) and trajectory.json (both timed); with
// TrajectoryFormat::MoveIt also trajectory_approach.yaml and trajectory_retreat.yaml
// (trajectory_msgs/JointTrajectory).
#include <filesystem>
#include <string>

#include "dmgplace/runtime/placement/placement_result.hpp"
#include "dmgplace/tools/motion/trajectory_files.hpp"
#include "dmgplace/tools/placement/placement_query_file.hpp"

namespace dmgplace::tools {

// One line per improvement for the terminal.
std::string solution_line(const runtime::PlacementSolution& s);
// The result as JSON text.
std::string result_json(const PlacementQueryFile& query, const runtime::PlacementResult& r,
                        const runtime::Kinematics& kin);
// Writes result.json, trace.csv, path.csv and the trajectories into `dir` (created), each atomically.
void write_placement_result(const std::filesystem::path& dir, const PlacementQueryFile& query,
                            const runtime::PlacementResult& r, const runtime::Kinematics& kin,
                            TrajectoryFormat format = TrajectoryFormat::Json);

}  // namespace dmgplace::tools
