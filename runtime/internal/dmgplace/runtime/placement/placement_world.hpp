#pragma once
// Everything a placement query runs against, built once from the three artifacts: the arm's
// kinematics, both collision layers with the environment, the held object's grasp graph, mesh and
// sphere cover, and the hand (the links rigid with the tool center point).
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/object_spheres.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/environment/environment_model.hpp"
#include "dmgplace/runtime/grasp/grasp_graph.hpp"
#include "dmgplace/runtime/placement/artifact_fit.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::runtime {

struct HandModel {
  std::vector<int> links;    // links rigid with the TCP (flange, hand, fingers)
  std::vector<int> fingers;  // hand links behind a finger joint: they may touch the held object
  std::vector<std::pair<int, Eigen::Isometry3d>> in_tcp;  // each hand link's pose in the TCP frame
};

// What the runtime builds from the held object's mesh alone: FCL's tree of it and its sphere
// cover. World::load builds them on a second core while the robot and the environment load.
struct HeldObjectModels {
  std::unique_ptr<CollisionMesh> mesh;
  SphereSet spheres;
  static HeldObjectModels build(const TriMesh& mesh);
};

class PlacementWorld {
 public:
  // The arm chain is the robot artifact's; its tip must be the gripper's TCP (z approach, y
  // closing). Finger joints are set to half of `finger_opening` (< 0: the gripper's maximum).
  // Refuses (dmgplace::Error naming the files) a set that does not fit together (artifact_fit.hpp).
  // `joint_values` sets joints outside the arm chain (another arm, a torso, a mobile base's lift)
  // for this world; the rest stay at the robot artifact's values. A name that is not such a joint
  // (unknown, in the chain, fixed, a mimic, a finger) or a value outside its limits is refused.
  // `held`, when valid, delivers the object's HeldObjectModels (built from the same mesh);
  // otherwise they are built here.
  PlacementWorld(formats::RobotArtifact robot, formats::ObjectArtifact object, formats::EnvironmentArtifact env,
                 double finger_opening = -1, const std::map<std::string, double>& joint_values = {},
                 std::future<HeldObjectModels> held = {});
  PlacementWorld(const PlacementWorld&) = delete;
  PlacementWorld& operator=(const PlacementWorld&) = delete;

  const Kinematics& kinematics() const { return *kin_; }
  const formats::RobotArtifact& robot() const { return robot_; }
  const formats::ObjectArtifact& object() const { return object_; }
  const EnvironmentModel& env() const { return env_; }
  const Scene& scene() const { return scene_; }
  const GraspGraph& grasp_graph() const { return *grasps_; }
  const ExactChecker& exact() const { return *exact_; }
  const CollisionMesh& object_mesh() const { return *object_mesh_; }
  const SphereSet& object_spheres() const { return object_spheres_; }
  const HandModel& hand() const { return hand_; }
  // How the three artifacts fit together: the warnings (errors refused construction).
  const ArtifactFit& fit() const { return fit_; }
  // How far the fingers open, closed to fully open (m, between the finger frames).
  double finger_travel() const;

  // Both layers with the object held at `tcp_in_object` (a grasp) and the fingers at that grasp's
  // `opening` (m; < 0: as kinematics() has them): shares all geometry. Object and hand are not
  // checked against each other (their relative pose is the grasp's, fixed).
  TwoLayerChecker grasp_checker(const Eigen::Isometry3d& tcp_in_object, double opening,
                                std::shared_ptr<CheckCounters> counters) const;
  // Both layers for the arm alone, empty-handed, the fingers at `opening` (< 0: as kinematics() has them).
  TwoLayerChecker arm_checker(std::shared_ptr<CheckCounters> counters, double opening = -1) const;
  // Exact, with the object also checked against the hand's non-finger links: the grasp itself.
  ExactChecker grasp_exact(const Eigen::Isometry3d& tcp_in_object, double opening) const;
  // The object released at `object_pose` (world), the arm free to move around it: the fingers may
  // touch it (released_exact), or nothing may (placed_exact: the hand has let go and withdrawn).
  // The fingers at `opening` (< 0: as kinematics() has them).
  ExactChecker released_exact(const Eigen::Isometry3d& object_pose, double opening = -1) const;
  ExactChecker placed_exact(const Eigen::Isometry3d& object_pose, double opening = -1) const;
  // The kinematics with the fingers at `opening` (< 0: kinematics()); lives as long as the world.
  const Kinematics& kinematics_at(double opening) const;
  // Hand-only exact test at a TCP pose (no arm, no IK): the grasp filter of Algorithm 3. Exact
  // because the hand works close to the support, where conservative spheres would reject it.
  // Fingers at `opening` (< 0: as the world's kinematics has them).
  bool hand_free(const Eigen::Isometry3d& tcp_world, double opening = -1) const;
  // Hand links' poses in the TCP frame with the fingers at `opening` (>= 0; tests, viewers).
  const std::vector<std::pair<int, Eigen::Isometry3d>>& hand_at(double opening) const {
    return fingers_at(opening).hand;
  }

 private:
  formats::RobotArtifact robot_;
  formats::ObjectArtifact object_;
  Scene scene_;
  EnvironmentModel env_;
  std::unique_ptr<Kinematics> kin_;
  std::unique_ptr<GraspGraph> grasps_;
  std::unique_ptr<ExactChecker> exact_;
  std::unique_ptr<SphereFieldChecker> fast_;
  std::unique_ptr<CollisionMesh> object_mesh_;
  SphereSet object_spheres_;
  HandModel hand_;
  ArtifactFit fit_;
  // Per finger opening: kinematics with the fingers there (the checkers point at it, so it lives
  // as long as the world) and the hand links' poses in the TCP frame.
  struct FingerSetting {
    std::unique_ptr<Kinematics> kin;
    std::vector<std::pair<int, Eigen::Isometry3d>> hand;
  };
  const FingerSetting& fingers_at(double opening) const;  // opening >= 0
  void set_fingers(Kinematics& kin, double opening) const;
  void set_robot_joints(const std::map<std::string, double>& values, const std::string& file);
  std::vector<std::pair<int, Eigen::Isometry3d>> hand_in_tcp(const Kinematics& kin) const;
  mutable std::mutex fingers_mutex_;
  mutable std::map<double, std::unique_ptr<FingerSetting>> fingers_;
};

}  // namespace dmgplace::runtime
