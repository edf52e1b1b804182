#pragma once
// Forward kinematics of 8 configurations at once in SIMD lanes, for the fast collision layer's
// lane checks: Kinematics::Lanes, the plan a Kinematics keeps for them (rebuilt whenever a joint
// value is set). Every step runs in lanes.hpp vectors; AVX2 + FMA where the CPU has them, else
// the portable x86-64 build (system/simd_dispatch.hpp). Private to the runtime.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::runtime {

// Link poses of kLanes configurations at once, structure of arrays: element e of link l's pose in
// lane k is pose[l][e][k], e = 0..8 the rotation row-major, 9..11 the translation. One lane per
// configuration, so each arithmetic step runs over all lanes in SIMD registers.
template <class T>
struct LinkPoseLanes {
  static constexpr int kLanes = 8;
  using Lanes = std::array<T, kLanes>;
  std::vector<std::array<Lanes, 12>> pose;
};
using LinkPoseLanesD = LinkPoseLanes<double>;
// In single precision: all 8 lanes in one AVX register per step. Kinematics::Lanes::float_pose_error
// bounds how far its positions are from the double ones.
using LinkPoseLanesF = LinkPoseLanes<float>;

struct Kinematics::Lanes {
  explicit Lanes(const Kinematics& kin);

  // Kinematics::link_poses for kLanes configurations q[0..kLanes) (each dof() values) in one pass.
  void link_poses(const double* const* q, LinkPoseLanesD& out) const;
  // The same in floats (joint values, sin and cos still in doubles, each rounded once).
  void link_poses(const double* const* q, LinkPoseLanesF& out) const;
  // Lane frames: a link that no chain joint moves relative to its parent (a flange, a hand, its
  // fingers at their set values) keeps one pose in the frame of its nearest ancestor that one
  // does move (or the root): frame(link), at frame_offset(link). frame_poses computes only the
  // frame links' poses (the others are left as they were), so a caller that carries its points
  // into their frames skips FK for the rest. Every link is its own frame when the base is not the
  // model's root. `version` is new whenever the offsets may have changed (a joint value set;
  // unique across objects): a caller keeping points in frames checks it first.
  int frame(int link) const { return frame_of_[std::size_t(link)]; }
  const Eigen::Isometry3d& frame_offset(int link) const { return frame_offset_[std::size_t(link)]; }
  void frame_poses(const double* const* q, LinkPoseLanesF& out) const;
  std::uint64_t version = 0;
  // A bound, in metres, on how far a point within `reach` of its link's origin, placed by a
  // LinkPoseLanesF pose in floats (rotation times point plus translation), can be from where the
  // double poses put it (prismatic joints within their limits; any angle).
  double float_pose_error(double reach) const;

  // Each joint in topological order: value = mult * q[slot] + offset (slot < 0: offset alone),
  // mimic chains folded in.
  struct Joint {
    int type = 0;  // 0 fixed, 1 revolute, 2 prismatic
    int parent = 0, child = 0, slot = -1;
    double mult = 1, offset = 0;
    double O[9], OK[9], OKK[9], t[3], a[3];  // origin rotation (row-major), Rodrigues terms, translation, O * axis
    bool quarter = false;                    // JointMotionTerms' quarter-turn form
    int perm[3] = {0, 1, 2}, axis = -1;
    double sign[3] = {1, 1, 1}, axis_sign = 1;
  };

 private:
  std::vector<Joint> plan_;
  // Per link its frame and its pose there, and plan_'s joints whose child is a frame, carried to
  // their parent's frame (frame_poses' plan).
  std::vector<int> frame_of_;
  std::vector<Eigen::Isometry3d> frame_offset_;
  std::vector<Joint> frame_plan_;
  std::vector<int> roots_;
  int base_ = -1;
  bool base_is_root_ = false;
  std::size_t links_ = 0;
  // float_pose_error's terms, over all links: rotation error (Frobenius), translation error.
  double float_rotation_error_ = 0, float_translation_error_ = 0;
  void build_plan(const Kinematics& kin);
  void build_frames();
  void bound_float_error(const Kinematics& kin);
};

}  // namespace dmgplace::runtime
