#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/runtime/robot/kinematics_lanes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/geometry/fast_sincos.hpp"

namespace dmgplace::runtime {
namespace {
// URDFs write a quarter turn as 1.57079632679 (cos = 4.9e-12) or 1.5708: entries this close to 0
// or +-1 are taken as exact, so the joint takes the quarter-turn form (JointMotionTerms). The
// change moves a link by under 1e-8 m, and every layer (spheres, exact, tables) sees the same model.
constexpr double kSnap = 1e-9;

// A joint that turns (a sincos per configuration): revolute, or continuous.
bool turns(const Joint& j) { return j.type == JointType::Revolute || j.type == JointType::Continuous; }

// Is O a signed permutation within kSnap? Then column c of O is sign[c] * e_perm[c], and O is
// made exactly that.
bool snap_quarter_turns(Eigen::Matrix3d& O, int perm[3], double sign[3]) {
  bool used[3] = {false, false, false};
  for (int c = 0; c < 3; ++c) {
    int at = -1;
    for (int r = 0; r < 3; ++r)
      if (std::abs(std::abs(O(r, c)) - 1) <= kSnap) at = r;
      else if (!(std::abs(O(r, c)) <= kSnap)) return false;
    if (at < 0 || used[at]) return false;
    used[at] = true;
    perm[c] = at;
    sign[c] = O(at, c) > 0 ? 1.0 : -1.0;
  }
  for (int c = 0; c < 3; ++c) O.col(c) = sign[c] * Eigen::Vector3d::Unit(perm[c]);
  return true;
}

// Is the unit axis a within kSnap of +-e_i? Then a is made exactly that and i returned, else -1.
int snap_axis(Eigen::Vector3d& a, double& sign) {
  for (int i = 0; i < 3; ++i)
    if (std::abs(std::abs(a[i]) - 1) <= kSnap && std::abs(a[(i + 1) % 3]) <= kSnap &&
        std::abs(a[(i + 2) % 3]) <= kSnap) {
      sign = a[i] > 0 ? 1.0 : -1.0;
      a = sign * Eigen::Vector3d::Unit(i);
      return i;
    }
  return -1;
}

RobotModel with_quarter_turns_snapped(RobotModel m) {
  for (auto& j : m.joints) {
    Eigen::Matrix3d O = j.origin.linear();
    int perm[3];
    double sign[3];
    if (snap_quarter_turns(O, perm, sign)) j.origin.linear() = O;
    double s;
    snap_axis(j.axis, s);
  }
  return m;
}
}  // namespace

Kinematics::Kinematics(const RobotModel& model, const std::string& base, const std::string& tip)
    : model_(std::make_shared<const RobotModel>(with_quarter_turns_snapped(model))) {
  base_ = model_->link_index(base);
  tip_ = model_->link_index(tip);
  if (base_ < 0) throw Error(model_->name, "arm base", "no link named '" + base + "'");
  if (tip_ < 0) throw Error(model_->name, "arm tip", "no link named '" + tip + "'");
  const std::size_t nl = model_->links.size(), nj = model_->joints.size();
  std::vector<int> parent_joint(nl, -1);
  for (std::size_t j = 0; j < nj; ++j) {
    const auto& jt = model_->joints[j];
    if (jt.child < 0 || std::size_t(jt.child) >= nl || jt.parent < 0 || std::size_t(jt.parent) >= nl)
      throw Error(model_->name, "joint '" + jt.name + "'", "link index out of range");
    parent_joint[std::size_t(jt.child)] = int(j);
  }
  // Path tip -> base.
  for (int link = tip_, steps = 0; link != base_; ++steps) {
    int j = parent_joint[std::size_t(link)];
    if (j < 0 || steps > int(nl))
      throw Error(model_->name, "arm chain", "'" + tip + "' does not descend from '" + base + "'");
    path_joints_.push_back(j);
    link = model_->joints[std::size_t(j)].parent;
  }
  std::reverse(path_joints_.begin(), path_joints_.end());
  path_moving_end_ = path_joints_.size();
  while (path_moving_end_ > 0 &&
         model_->joints[std::size_t(path_joints_[path_moving_end_ - 1])].type == JointType::Fixed)
    --path_moving_end_;
  for (std::size_t k = path_moving_end_; k < path_joints_.size(); ++k)
    path_tail_ = path_tail_ * model_->joints[std::size_t(path_joints_[k])].origin;
  chain_slot_.assign(nj, -1);
  for (int j : path_joints_) {
    const auto& jt = model_->joints[std::size_t(j)];
    if (jt.type == JointType::Fixed || jt.mimic >= 0) continue;
    chain_slot_[std::size_t(j)] = int(chain_joints_.size());
    chain_joints_.push_back(j);
    joint_names_.push_back(jt.name);
  }
  lower_.resize(dof());
  upper_.resize(dof());
  for (int i = 0; i < dof(); ++i) {
    const auto& jt = model_->joints[std::size_t(chain_joints_[std::size_t(i)])];
    const bool unlimited = jt.type == JointType::Continuous;
    lower_[i] = unlimited ? -M_PI : jt.lower;
    upper_[i] = unlimited ? M_PI : jt.upper;
  }
  fixed_values_.assign(nj, 0.0);
  // Topological order: a joint after the joint that places its parent link.
  std::vector<char> done(nj, 0);
  for (std::size_t pass = 0; pass <= nj && order_.size() < nj; ++pass)
    for (std::size_t j = 0; j < nj; ++j) {
      if (done[j]) continue;
      int pj = parent_joint[std::size_t(model_->joints[j].parent)];
      if (pj < 0 || done[std::size_t(pj)]) {
        order_.push_back(int(j));
        done[j] = 1;
      }
    }
  if (order_.size() != nj) throw Error(model_->name, "joints", "kinematic loop");
  for (std::size_t l = 0; l < nl; ++l)
    if (parent_joint[l] < 0) roots_.push_back(int(l));
  terms_.resize(nj);
  for (std::size_t j = 0; j < nj; ++j) {
    const auto& jt = model_->joints[j];
    Eigen::Matrix3d K;
    K << 0, -jt.axis.z(), jt.axis.y(), jt.axis.z(), 0, -jt.axis.x(), -jt.axis.y(), jt.axis.x(), 0;
    auto& m = terms_[j];
    m.OK = jt.origin.linear() * K;
    m.OKK = m.OK * K;
    m.Oa = jt.origin.linear() * jt.axis;
    Eigen::Matrix3d O = jt.origin.linear();
    Eigen::Vector3d axis = jt.axis;
    const bool permuted = snap_quarter_turns(O, m.perm, m.sign);
    m.axis = snap_axis(axis, m.axis_sign);
    m.quarter = permuted && (m.axis >= 0 || jt.type == JointType::Fixed || jt.type == JointType::Prismatic);
  }
  base_is_root_ = parent_joint[std::size_t(base_)] < 0;
  lanes_ = std::make_shared<const Lanes>(*this);
}

void Kinematics::set_joint_value(const std::string& joint, double value) {
  int j = model_->joint_index(joint);
  if (j < 0) throw Error(model_->name, "joint", "no joint named '" + joint + "'");
  if (chain_slot_[std::size_t(j)] >= 0) throw Error(model_->name, "joint '" + joint + "'", "is driven by the chain");
  fixed_values_[std::size_t(j)] = value;
  lanes_ = std::make_shared<const Lanes>(*this);
}

double Kinematics::joint_value(int j, const Eigen::VectorXd& q) const {
  const auto& jt = model_->joints[std::size_t(j)];
  if (jt.mimic >= 0) return jt.mimic_multiplier * joint_value(jt.mimic, q) + jt.mimic_offset;
  int slot = chain_slot_[std::size_t(j)];
  return slot >= 0 ? q[slot] : fixed_values_[std::size_t(j)];
}

// Always inlined: in link_poses' loop a call made forward kinematics measurably slower.
__attribute__((always_inline)) inline void Kinematics::compose(int j, const Eigen::VectorXd& q,
                                                               const Eigen::Isometry3d& parent,
                                                               Eigen::Isometry3d& child, const double* sincos) const {
  const auto& jt = model_->joints[std::size_t(j)];
  const auto& m = terms_[std::size_t(j)];
  const auto P = parent.linear();
  auto C = child.linear();
  Eigen::Vector3d t = jt.origin.translation();
  if (jt.type == JointType::Prismatic) t += joint_value(j, q) * m.Oa;
  child.translation().noalias() = P * t;
  child.translation() += parent.translation();
  const bool revolute = turns(jt);
  if (m.quarter) {
    for (int c = 0; c < 3; ++c) C.col(c) = m.sign[c] * P.col(m.perm[c]);
    if (!revolute) return;
    // Turning about e_axis mixes the two columns across it: (u, v) -> (c u + s v, c v - s u).
    double s, c;
    if (sincos) s = sincos[0], c = sincos[1];
    else fast_sincos(joint_value(j, q), s, c);
    s *= m.axis_sign;
    const int a = (m.axis + 1) % 3, b = (m.axis + 2) % 3;
    const Eigen::Vector3d u = C.col(a), v = C.col(b);
    C.col(a) = c * u + s * v;
    C.col(b) = c * v - s * u;
    return;
  }
  if (!revolute) {
    C.noalias() = P * jt.origin.linear();
    return;
  }
  double s, c;
  if (sincos) s = sincos[0], c = sincos[1];
  else fast_sincos(joint_value(j, q), s, c);
  const Eigen::Matrix3d R = jt.origin.linear() + s * m.OK + (1 - c) * m.OKK;
  C.noalias() = P * R;
}

void Kinematics::link_poses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& poses) const {
  // Every link but the roots is written below (joints in topological order): only roots are reset.
  if (poses.size() != model_->links.size()) poses.assign(model_->links.size(), Eigen::Isometry3d::Identity());
  for (int r : roots_) poses[std::size_t(r)].setIdentity();
  // Every turning joint's sine and cosine first, at once in SIMD lanes (fast_sincos_many): the
  // Panda's forward kinematics took less time than with one joint's at a time.
  constexpr std::size_t kAtOnce = 64;
  double value[kAtOnce], sc[2][kAtOnce];
  const bool at_once = order_.size() <= kAtOnce;
  int n = 0;
  if (at_once) {
    for (int j : order_)
      if (turns(model_->joints[std::size_t(j)])) value[n++] = joint_value(j, q);
    fast_sincos_many(value, n, sc[0], sc[1]);
  }
  // Express the tree in the base frame: first the root-to-base transform, then invert it.
  // child = parent * origin * motion, the motion folded into the origin's rotation (revolute) or
  // translation (prismatic) in place: no 4x4 temporary per joint.
  int k = 0;
  for (int j : order_) {
    const auto& jt = model_->joints[std::size_t(j)];
    double pair[2];
    const double* given = nullptr;
    if (at_once && turns(jt)) {
      pair[0] = sc[0][k];
      pair[1] = sc[1][k];
      ++k;
      given = pair;
    }
    compose(j, q, poses[std::size_t(jt.parent)], poses[std::size_t(jt.child)], given);
  }
  if (base_is_root_) return;
  const Eigen::Isometry3d to_base = poses[std::size_t(base_)].inverse();
  for (auto& p : poses) p = to_base * p;
}

Eigen::Isometry3d Kinematics::tip_pose(const Eigen::VectorXd& q) const { return chain_pose(q, nullptr); }

void Kinematics::jacobian(const Eigen::VectorXd& q, Jacobian& J) const { chain_pose(q, &J); }

Eigen::Isometry3d Kinematics::tip_pose_and_jacobian(const Eigen::VectorXd& q, Jacobian& J) const {
  return chain_pose(q, &J);
}

Eigen::Isometry3d Kinematics::chain_pose(const Eigen::VectorXd& q, Jacobian* J) const {
  // Base to tip as link_poses composes it (each joint's motion folded into its origin: 3x3
  // products, no 4x4 temporaries). A joint's axis and origin in the base frame give its column; a
  // mimic joint on the path adds its motion to the column of the joint it follows.
  if (J) J->setZero(6, dof());
  Eigen::Isometry3d T[2] = {Eigen::Isometry3d::Identity(),
                            Eigen::Isometry3d::Identity()};  // parent, child, alternating
  int cur = 0;
  Eigen::Vector3d axes[64], origins[64];
  int cols[64];
  double mult[64];
  bool prismatic[64];
  int n = 0;
  for (std::size_t k = 0; k < path_moving_end_; ++k) {
    const int j = path_joints_[k];
    const auto& jt = model_->joints[std::size_t(j)];
    compose(j, q, T[cur], T[1 - cur]);
    const Eigen::Vector3d axis = T[cur].linear() * terms_[std::size_t(j)].Oa;  // in the base frame
    cur = 1 - cur;
    if (!J || jt.type == JointType::Fixed || n >= 64) continue;
    int col = chain_slot_[std::size_t(j)];
    double m = 1.0;
    if (jt.mimic >= 0) {
      col = chain_slot_[std::size_t(jt.mimic)];
      m = jt.mimic_multiplier;
    }
    if (col < 0) continue;
    axes[n] = axis;
    origins[n] = T[cur].translation();  // a revolute joint's origin, where its column's lever starts
    cols[n] = col;
    mult[n] = m;
    prismatic[n] = jt.type == JointType::Prismatic;
    ++n;
  }
  Eigen::Isometry3d tip = T[cur] * path_tail_;  // the fixed joints that end the path, in one step
  const Eigen::Vector3d p = tip.translation();
  for (int i = 0; i < n; ++i) {
    if (prismatic[i]) {
      J->block<3, 1>(0, cols[i]) += mult[i] * axes[i];
    } else {
      J->block<3, 1>(0, cols[i]) += mult[i] * axes[i].cross(p - origins[i]);
      J->block<3, 1>(3, cols[i]) += mult[i] * axes[i];
    }
  }
  tip.makeAffine();
  return tip;
}

std::vector<char> Kinematics::moving_links() const {
  std::vector<char> moving(model_->links.size(), 0);
  const Eigen::VectorXd q0 = 0.5 * (lower_ + upper_);
  std::vector<Eigen::Isometry3d> a, b;
  link_poses(q0, a);
  // A link moves when perturbing any chain joint moves it.
  for (int i = 0; i < dof(); ++i) {
    Eigen::VectorXd q = q0;
    q[i] += 0.1;
    link_poses(q, b);
    for (std::size_t l = 0; l < a.size(); ++l) moving[l] |= !a[l].isApprox(b[l], 1e-12);
  }
  return moving;
}

bool Kinematics::within_limits(const Eigen::VectorXd& q, double tol) const {
  if (q.size() != dof()) return false;
  for (int i = 0; i < dof(); ++i)
    if (!(q[i] >= lower_[i] - tol && q[i] <= upper_[i] + tol)) return false;
  return true;
}

}  // namespace dmgplace::runtime
