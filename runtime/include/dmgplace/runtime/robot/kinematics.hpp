#pragma once
// Forward kinematics of a whole robot tree driven by one serial chain's joints, and the chain tip's
// geometric Jacobian. Our own Eigen code (no KDL: see docs). Hot-path calls do not allocate once
// the output containers have their size.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dmgplace/formats/robot_model.hpp"

namespace dmgplace::runtime {

using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic>;  // rows: linear velocity, angular velocity

// Link poses of kLanes configurations at once, structure of arrays: element e of link l's pose in
// lane k is pose[l][e][k], e = 0..8 the rotation row-major, 9..11 the translation. One lane per
// configuration, so each arithmetic step runs over all lanes in SIMD registers.
template <class T>
struct PoseBatchOf {
  static constexpr int kLanes = 8;
  using Lanes = std::array<T, kLanes>;
  std::vector<std::array<Lanes, 12>> pose;
};
using PoseBatch = PoseBatchOf<double>;
// In single precision: all 8 lanes in one AVX register per step. Kinematics::float_pose_error
// bounds how far its positions are from the double ones.
using PoseBatchF = PoseBatchOf<float>;

class Kinematics {
 public:
  // Throws dmgplace::Error when base/tip are not links or tip does not descend from base. Joint
  // origins within 1e-9 of quarter turns, and axes within 1e-9 of a frame axis, are made exact
  // (URDFs write pi/2 to a few digits); model() is the model so cleaned, which every layer uses.
  Kinematics(const RobotModel& model, const std::string& base, const std::string& tip);

  int dof() const { return int(chain_joints_.size()); }
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }
  const RobotModel& model() const { return *model_; }
  int tip_link() const { return tip_; }
  int base_link() const { return base_; }

  // Index in q of a model joint, or -1 when the chain does not drive it.
  int chain_slot(int joint) const {
    return joint >= 0 && std::size_t(joint) < chain_slot_.size() ? chain_slot_[std::size_t(joint)] : -1;
  }

  // Values of joints that are not part of the chain (e.g. the gripper fingers); default 0.
  void set_joint_value(const std::string& joint, double value);
  // A model joint's value at chain configuration q (chain, mimic or set value).
  double joint_value(int joint, const Eigen::VectorXd& q) const;

  // Pose of every link in the base link's frame; links not below the base stay identity-relative
  // to it through their ancestors (the whole tree is expressed in the base frame).
  void link_poses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& poses) const;
  Eigen::Isometry3d tip_pose(const Eigen::VectorXd& q) const;
  // link_poses for PoseBatch::kLanes configurations q[0..kLanes) (each dof() values) in one pass:
  // AVX2 + FMA where the CPU has them (system/simd_dispatch.hpp).
  void link_poses_batch(const double* const* q, PoseBatch& out) const;
  // The same in floats (joint values, sin and cos still in doubles, each rounded once).
  void link_poses_batch(const double* const* q, PoseBatchF& out) const;
  // Batch frames: a link that no chain joint moves relative to its parent (a flange, a hand, its
  // fingers at their set values) keeps one pose in the frame of its nearest ancestor that one
  // does move (or the root): batch_frame(link), at batch_frame_offset(link). frame_poses_batch
  // computes only the frame links' poses (the others are left as they were), so a caller that
  // carries its points into their frames skips FK for the rest. Every link is its own frame when
  // the base is not the model's root. plan_version() changes whenever the offsets may have (a
  // joint value set; unique across objects): a caller keeping points in frames checks it first.
  int batch_frame(int link) const { return frame_of_[std::size_t(link)]; }
  const Eigen::Isometry3d& batch_frame_offset(int link) const { return frame_offset_[std::size_t(link)]; }
  void frame_poses_batch(const double* const* q, PoseBatchF& out) const;
  std::uint64_t plan_version() const { return plan_version_; }
  // A bound, in metres, on how far a point within `reach` of its link's origin, placed by a
  // PoseBatchF pose in floats (rotation times point plus translation), can be from where the
  // double poses put it (prismatic joints within their limits; any angle).
  double float_pose_error(double reach) const;
  // Geometric Jacobian of the tip origin in the base frame.
  void jacobian(const Eigen::VectorXd& q, Jacobian& J) const;
  // Tip pose and Jacobian in one pass.
  Eigen::Isometry3d tip_pose_and_jacobian(const Eigen::VectorXd& q, Jacobian& J) const;

  bool within_limits(const Eigen::VectorXd& q, double tol = 1e-9) const;
  // Per link: does its pose depend on the chain's joints? (Static links need no collision checks
  // against a static world.)
  std::vector<char> moving_links() const;

 private:
  // child = parent x joint j's frame at q (parent and child distinct): link_poses and chain_pose
  // compose these. A quarter-turn joint (JointMotionTerms::quarter) takes the parent's columns
  // permuted and turns two of them; others use the Rodrigues terms.
  // `sincos`: the joint's sine and cosine when the caller has them (else computed here).
  void compose(int j, const Eigen::VectorXd& q, const Eigen::Isometry3d& parent, Eigen::Isometry3d& child,
               const double* sincos = nullptr) const;
  // The tip's pose, and with J its Jacobian (tip_pose, jacobian, tip_pose_and_jacobian).
  Eigen::Isometry3d chain_pose(const Eigen::VectorXd& q, Jacobian* J) const;
  // Per joint, Rodrigues' formula folded into the origin (rotation O, translation t): the child
  // frame's rotation is O + sin(q) OK + (1 - cos(q)) OKK for a revolute joint (K the axis'
  // cross-product matrix), its translation t + q Oa for a prismatic one. Saves building an
  // angle-axis rotation per joint.
  struct JointMotionTerms {
    Eigen::Matrix3d OK, OKK;
    Eigen::Vector3d Oa;
    // Most arms' joints (the Panda's, UR's, KUKA's) have origins turned by quarter turns and
    // axes along a frame axis. Then the origin rotation is a signed permutation (column c is
    // sign[c] * e_perm[c]) and a revolute joint turns only the two columns across its axis
    // (axis_sign * e_axis): 12 products per joint instead of 54. `quarter`: the joint is of this
    // form (a fixed or prismatic joint needs only the permutation).
    bool quarter = false;
    int perm[3] = {0, 1, 2};
    double sign[3] = {1, 1, 1};
    int axis = -1;  // -1: not along a frame axis
    double axis_sign = 1;
  };
  std::vector<JointMotionTerms> terms_;
  std::vector<int> roots_;  // links without a parent joint

 public:
  // link_poses_batch's view of each joint in topological order, rebuilt when a set value changes:
  // value = mult * q[slot] + offset (slot < 0: offset alone), mimic chains folded in.
  struct BatchJoint {
    int type = 0;  // 0 fixed, 1 revolute, 2 prismatic
    int parent = 0, child = 0, slot = -1;
    double mult = 1, offset = 0;
    double O[9], OK[9], OKK[9], t[3], a[3];  // origin rotation (row-major), Rodrigues terms, translation, O * axis
    bool quarter = false;  // JointMotionTerms' quarter-turn form
    int perm[3] = {0, 1, 2}, axis = -1;
    double sign[3] = {1, 1, 1}, axis_sign = 1;
  };

 private:
  std::vector<BatchJoint> batch_plan_;
  void build_batch_plan();
  // The batch frames (batch_frame): per link its frame and its pose there, and batch_plan_'s
  // joints whose child is a frame, carried to their parent's frame (frame_poses_batch's plan).
  // Built with batch_plan_.
  std::vector<int> frame_of_;
  std::vector<Eigen::Isometry3d> frame_offset_;
  std::vector<BatchJoint> frame_plan_;
  std::uint64_t plan_version_ = 0;
  void build_batch_frames();
  void bound_float_error();
  // float_pose_error's terms, over all links: rotation error (Frobenius), translation error.
  double float_rotation_error_ = 0, float_translation_error_ = 0;

  std::shared_ptr<const RobotModel> model_;  // shared by copies (e.g. one per finger opening)
  int base_ = -1, tip_ = -1;
  bool base_is_root_ = false;
  std::vector<int> chain_joints_;        // independent moving joints from base to tip
  std::vector<int> path_joints_;         // every joint from base to tip (fixed included), in order
  // The fixed joints that end the path (a wrist flange, a hand, a TCP) as one transform:
  // chain_pose composes path_joints_[0, path_moving_end_) and then this.
  std::size_t path_moving_end_ = 0;
  Eigen::Isometry3d path_tail_ = Eigen::Isometry3d::Identity();
  std::vector<int> order_;               // joints in topological order (parents first)
  std::vector<int> chain_slot_;          // joint -> index in q, or -1
  std::vector<double> fixed_values_;     // joint values of non-chain joints
  std::vector<std::string> joint_names_;
  Eigen::VectorXd lower_, upper_;
};

}  // namespace dmgplace::runtime
