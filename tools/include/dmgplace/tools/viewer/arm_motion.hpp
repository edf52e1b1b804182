#pragma once
// The robot's motion as the page plays it, in real time: the pusher's in-hand actions, the
// transport, the release and the retreat, sampled from the result's timed trajectories, with every
// drawn link's world pose and the object's pose per frame.
#include <vector>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/tools/viewer/view_result.hpp"

namespace dmgplace::tools::viewer {

struct ArmMotion {
  std::vector<int> links;  // robot links drawn: those with collision geometry
  int frames = 0;
  std::vector<float> frame_times;    // s from the start of the first push (or of the transport), not decreasing
  std::vector<float> link_poses;     // frames x links x 7 (x, y, z, qx, qy, qz, qw), world
  std::vector<float> object_poses;   // frames x 7: in the hand along the path, at rest during the retreat
  std::vector<int> waypoint_frames;  // the frame of each path waypoint, then of each retreat waypoint
  int retreat_frame = -1;            // first frame after the release; -1: no retreat
  std::vector<int> push_frames;      // the first frame of each in-hand action the pusher performs
  Eigen::Isometry3d object_initial = Eigen::Isometry3d::Identity();  // FK_tip(q0) * initial_grasp^-1
};

// Frames every `frame_period` s of the timed trajectories (coarser when that would exceed
// `max_frames`), and at each phase's end; a result without timing (older ones) plays its paths at a
// nominal joint speed. A push's object moves from its pose before the action to its pose after
// while the pusher goes from the push's first contact waypoint to its last. Unsolved results give
// one frame at the start. Fingers are set to half the grasp
// opening while holding, to half the result's release opening during the retreat (`open_width`
// where the result has none) and to half of `open_width` otherwise. Throws dmgplace::Error (naming the
// result file) when the result's joints are not the robot's arm chain.
ArmMotion sample_arm_motion(const ViewResult& r, const formats::RobotArtifact& robot, double open_width,
                            double frame_period = 1.0 / 30, int max_frames = 2400);

}  // namespace dmgplace::tools::viewer
