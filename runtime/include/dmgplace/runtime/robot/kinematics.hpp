#pragma once
// Forward kinematics of a whole robot tree driven by one serial chain's joints, and the chain tip's
// geometric Jacobian. Our own Eigen code (no KDL: see docs). Hot-path calls do not allocate once
// the output containers have their size.
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "dmgplace/formats/robot_model.hpp"

namespace dmgplace::runtime {

using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic>;  // rows: linear velocity, angular velocity

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
  // Forward kinematics in SIMD lanes, for the runtime's own collision checks (not installed:
  // robot/kinematics_lanes.hpp); rebuilt whenever a joint value is set.
  struct Lanes;
  const Lanes& lanes() const { return *lanes_; }
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

  std::shared_ptr<const Lanes> lanes_;  // shared by copies until a joint value is set

  std::shared_ptr<const RobotModel> model_;  // shared by copies (e.g. one per finger opening)
  int base_ = -1, tip_ = -1;
  bool base_is_root_ = false;
  std::vector<int> chain_joints_;  // independent moving joints from base to tip
  std::vector<int> path_joints_;   // every joint from base to tip (fixed included), in order
  // The fixed joints that end the path (a wrist flange, a hand, a TCP) as one transform:
  // chain_pose composes path_joints_[0, path_moving_end_) and then this.
  std::size_t path_moving_end_ = 0;
  Eigen::Isometry3d path_tail_ = Eigen::Isometry3d::Identity();
  std::vector<int> order_;            // joints in topological order (parents first)
  std::vector<int> chain_slot_;       // joint -> index in q, or -1
  std::vector<double> fixed_values_;  // joint values of non-chain joints
  std::vector<std::string> joint_names_;
  Eigen::VectorXd lower_, upper_;
};

}  // namespace dmgplace::runtime
