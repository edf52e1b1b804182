#include "dmgplace/runtime/placement/placement_world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::runtime {
namespace {
// Links whose pose relative to the tip no chain joint changes.
std::vector<int> rigid_with_tip(const Kinematics& kin) {
  const int n = kin.dof();
  const Eigen::VectorXd q0 = 0.5 * (kin.lower() + kin.upper());
  std::vector<Eigen::Isometry3d> a, b;
  kin.link_poses(q0, a);
  const Eigen::Isometry3d tip_a = a[std::size_t(kin.tip_link())];
  std::vector<char> rigid(a.size(), 1);
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd q = q0;
    q[i] += 0.1;
    kin.link_poses(q, b);
    const Eigen::Isometry3d tip_b = b[std::size_t(kin.tip_link())];
    for (std::size_t l = 0; l < a.size(); ++l)
      rigid[l] &= (tip_a.inverse() * a[l]).isApprox(tip_b.inverse() * b[l], 1e-9);
  }
  // A link that no joint moves at all (the base) is rigid with nothing that moves.
  const auto moving = kin.moving_links();
  std::vector<int> out;
  for (std::size_t l = 0; l < a.size(); ++l)
    if (rigid[l] && moving[l]) out.push_back(int(l));
  return out;
}

bool in_chain(const Kinematics& kin, const std::string& joint) {
  return std::find(kin.joint_names().begin(), kin.joint_names().end(), joint) != kin.joint_names().end();
}
}  // namespace

PlacementWorld::PlacementWorld(formats::RobotArtifact robot, formats::ObjectArtifact object,
                               formats::EnvironmentArtifact env, double finger_opening,
                               const std::map<std::string, double>& joint_values, std::future<HeldObjectModels> held)
    : robot_(std::move(robot)), object_(std::move(object)) {
  // Artifacts built in memory have no file name: say which kind instead.
  const auto name = [](const formats::ArtifactHeader& h, const char* kind) {
    return h.source_file.empty() ? std::string("<") + kind + " artifact>" : h.source_file;
  };
  if (env.sdf.empty())
    throw Error(name(env.header, "environment"), "/fields/sdf",
                "the artifact has no distance field; bake it with `dmgplace bake-env`");
  if (env.clearance.empty())
    throw Error(name(env.header, "environment"), "/fields/clearance",
                "the artifact has no clearance field; bake it with `dmgplace bake-env`");
  if (object_.mesh.empty()) throw Error(name(object_.header, "object"), "/mesh", "empty mesh");
  if (env.scene.objects.empty() && env.scene.points.rows() == 0)
    throw Error(name(env.header, "environment"), "/scene", "no obstacles and no scan points: nothing to place on");
  if (finger_opening > object_.dmg.gripper.max_opening + 1e-9 || !(std::isfinite(finger_opening)))
    throw Error(name(object_.header, "object"), "/dmg/gripper",
                "the initial grasp's opening " + std::to_string(finger_opening) + " m exceeds the gripper's maximum " +
                    std::to_string(object_.dmg.gripper.max_opening) + " m");
  const FitNames names{name(robot_.header, "robot"), name(object_.header, "object"), name(env.header, "environment")};
  scene_ = env.scene;
  env_ = make_environment_model(std::move(env));
  kin_ = std::make_unique<Kinematics>(robot_.model, robot_.model.arm_base, robot_.model.arm_tip);
  const auto& model = robot_.model;
  hand_.links = rigid_with_tip(*kin_);
  set_fingers(*kin_, finger_opening >= 0 ? finger_opening : object_.dmg.gripper.max_opening);
  // Fingers: hand links below a movable non-chain joint (children first reached through one).
  for (int l : hand_.links) {
    int link = l;
    bool finger = false;
    while (!finger) {
      auto it = std::find_if(model.joints.begin(), model.joints.end(), [&](const Joint& j) { return j.child == link; });
      if (it == model.joints.end() || link == kin_->tip_link()) break;
      finger = it->type != JointType::Fixed && !in_chain(*kin_, it->name);
      link = it->parent;
      if (std::find(hand_.links.begin(), hand_.links.end(), link) == hand_.links.end()) break;
    }
    if (finger) hand_.fingers.push_back(l);
  }
  set_robot_joints(joint_values, names.robot);
  hand_.in_tcp = hand_in_tcp(*kin_);
  fit_ = check_fit(object_, env_.regions, *kin_, finger_travel(), int(hand_.fingers.size()), names);
  if (!fit_.ok()) {
    std::string all;
    for (const auto& e : fit_.errors) all += (all.empty() ? "" : "; ") + e;
    throw Error(names.robot, "artifact set", all);
  }
  grasps_ = std::make_unique<GraspGraph>(object_);
  exact_ = std::make_unique<ExactChecker>(*kin_, scene_);
  fast_ = std::make_unique<SphereFieldChecker>(*kin_, robot_.spheres, env_.sdf, env_.sdf_band);
  fast_->set_self_tables(robot_.self_tables);
  fast_->set_exact_obstacles(PrimitiveObstacles::from_scene(scene_));  // null unless all primitives
  HeldObjectModels models = held.valid() ? held.get() : HeldObjectModels::build(object_.mesh);
  object_mesh_ = std::move(models.mesh);
  object_spheres_ = std::move(models.spheres);
}

HeldObjectModels HeldObjectModels::build(const TriMesh& mesh) {
  return {std::make_unique<CollisionMesh>(mesh), cover_object(mesh)};
}

void PlacementWorld::set_fingers(Kinematics& kin, double opening) const {
  // Finger joints: movable joints outside the chain whose child is a hand link; each finger
  // travels half the opening (mimic joints follow their leader).
  for (const auto& j : kin.model().joints) {
    if (j.type == JointType::Fixed || in_chain(kin, j.name)) continue;
    if (std::find(hand_.links.begin(), hand_.links.end(), j.child) == hand_.links.end()) continue;
    if (j.mimic < 0) kin.set_joint_value(j.name, std::clamp(0.5 * opening, j.lower, j.upper));
  }
}

void PlacementWorld::set_robot_joints(const std::map<std::string, double>& values, const std::string& file) {
  const auto& m = robot_.model;
  for (const auto& [name, value] : values) {
    const int j = m.joint_index(name);
    const std::string where = "joint '" + name + "'";
    if (j < 0) throw Error(file, where, "no joint of that name in robot '" + m.name + "'");
    const Joint& jt = m.joints[std::size_t(j)];
    if (kin_->chain_slot(j) >= 0)
      throw Error(file, where, "is a joint of the planning chain: it belongs in the start configuration");
    if (jt.type == JointType::Fixed)
      throw Error(file, where, "is fixed (in the URDF, or frozen by bake-robot --fixed-joints)");
    if (jt.mimic >= 0)
      throw Error(file, where, "follows '" + m.joints[std::size_t(jt.mimic)].name + "' (mimic): set that one");
    if (std::find(hand_.links.begin(), hand_.links.end(), jt.child) != hand_.links.end())
      throw Error(file, where, "moves a finger: fingers follow each grasp's opening");
    if (!std::isfinite(value) ||
        (jt.type != JointType::Continuous && (value < jt.lower - 1e-9 || value > jt.upper + 1e-9)))
      throw Error(file, where,
                  "value " + std::to_string(value) + " outside its limits [" + std::to_string(jt.lower) + ", " +
                      std::to_string(jt.upper) + "]");
    kin_->set_joint_value(name, value);
  }
}

std::vector<std::pair<int, Eigen::Isometry3d>> PlacementWorld::hand_in_tcp(const Kinematics& kin) const {
  std::vector<Eigen::Isometry3d> poses;
  kin.link_poses(0.5 * (kin.lower() + kin.upper()), poses);
  const Eigen::Isometry3d tip_inv = poses[std::size_t(kin.tip_link())].inverse();
  std::vector<std::pair<int, Eigen::Isometry3d>> out;
  for (int l : hand_.links) out.emplace_back(l, tip_inv * poses[std::size_t(l)]);
  return out;
}

const PlacementWorld::FingerSetting& PlacementWorld::fingers_at(double opening) const {
  std::lock_guard<std::mutex> lock(fingers_mutex_);
  auto& slot = fingers_[opening];  // exact value: each grasp's own (a DMG has one per node)
  if (!slot) {
    slot = std::make_unique<FingerSetting>();
    slot->kin = std::make_unique<Kinematics>(*kin_);  // shares the model; only finger values differ
    set_fingers(*slot->kin, opening);
    slot->hand = hand_in_tcp(*slot->kin);
  }
  return *slot;
}

double PlacementWorld::finger_travel() const {
  // Spread of the finger frames along the closing axis, fingers closed and fully open.
  auto gap = [&](double opening) {
    Kinematics k(*kin_);
    set_fingers(k, opening);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& [link, pose] : hand_in_tcp(k))
      if (std::find(hand_.fingers.begin(), hand_.fingers.end(), link) != hand_.fingers.end())
        lo = std::min(lo, pose.translation().y()), hi = std::max(hi, pose.translation().y());
    return hi > lo ? hi - lo : 0.0;
  };
  return gap(1e3) - gap(0);  // driven to their upper and lower limits
}

const Kinematics& PlacementWorld::kinematics_at(double opening) const {
  return opening >= 0 ? *fingers_at(opening).kin : *kin_;
}

TwoLayerChecker PlacementWorld::grasp_checker(const Eigen::Isometry3d& tcp_in_object, double opening,
                                              std::shared_ptr<CheckCounters> counters) const {
  const Kinematics& kin = kinematics_at(opening);
  const Eigen::Isometry3d object_in_tip = tcp_in_object.inverse();
  AttachedSpheres att;
  att.link = kin_->tip_link();
  // The object never moves against the hand: pairs with any hand link would only ever repeat the
  // grasp's own check (PerGraspCheckers::usable), so both layers skip them.
  att.touching_links = hand_.links;
  for (std::size_t i = 0; i < object_spheres_.centers.size(); ++i) {
    att.centers.push_back(object_in_tip * object_spheres_.centers[i]);
    att.radii.push_back(object_spheres_.radii[i]);
  }
  return TwoLayerChecker(
      fast_->with_kinematics(kin).with_attached(std::move(att)),
      exact_->with_kinematics(kin).with_attached(*object_mesh_, kin_->tip_link(), object_in_tip, hand_.links),
      std::move(counters));
}

TwoLayerChecker PlacementWorld::arm_checker(std::shared_ptr<CheckCounters> counters, double opening) const {
  if (opening < 0) return TwoLayerChecker(*fast_, *exact_, std::move(counters));
  const Kinematics& kin = kinematics_at(opening);
  return TwoLayerChecker(fast_->with_kinematics(kin), exact_->with_kinematics(kin), std::move(counters));
}

ExactChecker PlacementWorld::grasp_exact(const Eigen::Isometry3d& tcp_in_object, double opening) const {
  return exact_->with_kinematics(kinematics_at(opening))
      .with_attached(*object_mesh_, kin_->tip_link(), tcp_in_object.inverse(), hand_.fingers);
}

ExactChecker PlacementWorld::released_exact(const Eigen::Isometry3d& object_pose, double opening) const {
  return exact_->with_kinematics(kinematics_at(opening))
      .with_attached(*object_mesh_, kin_->base_link(), object_pose, hand_.fingers);
}

ExactChecker PlacementWorld::placed_exact(const Eigen::Isometry3d& object_pose, double opening) const {
  return exact_->with_kinematics(kinematics_at(opening))
      .with_attached(*object_mesh_, kin_->base_link(), object_pose, {});
}

bool PlacementWorld::hand_free(const Eigen::Isometry3d& tcp_world, double opening) const {
  thread_local std::vector<std::pair<int, Eigen::Isometry3d>> poses;
  poses = opening >= 0 ? fingers_at(opening).hand : hand_.in_tcp;
  for (auto& [link, pose] : poses) pose = tcp_world * pose;
  return exact_->links_free(poses);
}

}  // namespace dmgplace::runtime
