#pragma once
// Grasp selection (the paper's Algorithm 3). Walking up from the sampled node to the root (the
// root's own cache excluded), the grasps cached on the way form an ordered set G, nearest node
// first; with nothing cached G = {g0}. Each grasp of G whose hand is free of the environment at
// the sampled pose is returned with probability p_accept. Otherwise a grasp is drawn uniformly
// from G(g0) \ G (from all of G(g0) when G covers it).
//
// Beyond the paper: that last draw may be hand-filtered: up to `hand_tries` uniform draws whose
// hand is checked at the pose, the first that fits taken (a uniform draw among the grasps whose
// hand fits); when none fits, the sample has no grasp and skips IK (a colliding hand cannot give
// a collision-free arm, and IK successes there would credit the node with a reachability it does
// not have). 0 is the paper's Algorithm 3 exactly. Where the initial grasp blocks and nothing is
// cached yet, this is what finds the first reachable grasp (docs/perf-log.md).
//
// The random-grasp ablation draws uniformly from G(g0); no-regrasp always returns g0.
// G(g0) here is the reachable grasps with which the start configuration is collision-free (a grasp
// the arm cannot hold at q0 cannot start a path); draws skip the others.
//
// The cache (the paper's P_s) lives here, beside the selector: a grasp is cached at a node and
// all its ancestors as soon as it reached a pose sampled below that node kinematically (IK
// solution, arm and object free), and again after local optimisation of a reached placement.
//
// Beyond the paper: after the first solution the acceptance learns. From then on every try of a
// grasp at a pose where the object is free is recorded at the sampled node and its ancestors
// (reached kinematically or not). A cached grasp that never reached in its t tries at the nearest
// node (from the sampled one up) with a record of it is taken with p_accept / (t + 1); one that
// reached there at all, or has no record, with p_accept. A grasp cached on a face because it
// reaches one region is offered on every region of that face; where it never reaches, the fixed
// p_accept kept offering it and drew a grasp outside the cache with probability (1 - p_accept)^|G|,
// and the search stayed on its plateau. (Before the first solution the cache's pull is what finds
// a grasp where g0 blocks; decaying it then solved fewer blocked runs.)
#include <cstdint>
#include <functional>
#include <random>
#include <unordered_map>
#include <vector>

#include "dmgplace/runtime/placement/per_grasp_checkers.hpp"
#include "dmgplace/runtime/placement/placement_query.hpp"
#include "dmgplace/runtime/placement/placement_tree.hpp"

namespace dmgplace::runtime {

struct GraspChoice {
  int grasp = -1;       // index into PerGraspCheckers (0 is g0); -1: none (no usable grasp, or no hand fits)
  bool cached = false;  // taken from the cache (or g0 accepted as the empty cache's stand-in)
};

class GraspSelector {
 public:
  // hand_free(g, object_pose): grasp g's hand is free of the environment with the object there.
  using HandFree = std::function<bool(int grasp, const Eigen::Isometry3d& object_pose)>;
  GraspSelector(PerGraspCheckers& per_grasp, const PlacementTree& tree, PlacementVariant variant, double p_accept,
                int hand_tries, HandFree hand_free);
  GraspChoice select(int node, const Eigen::Isometry3d& object_pose, std::mt19937_64& rng);
  // Records that `grasp` kinematically reached a pose sampled below `node`.
  void cache(int node, int grasp);
  // Records a try of `grasp` at a pose sampled below `node` (the object free there): whether it
  // reached it kinematically. Only `full` keeps records.
  void record(int node, int grasp, bool reached);
  // The factor on p_accept for `grasp` at `node`: 1 / (t + 1) when the nearest record has t tries
  // and none reached, else 1.
  double acceptance(int node, int grasp) const;
  // The ordered set G for `node` (nearest node first, no repeats); empty when nothing is cached.
  std::vector<int> cached(int node) const;
  long hand_checks() const { return hand_checks_; }

 private:
  int draw(bool skip_cached, std::mt19937_64& rng);  // uniform over usable grasps (not in G)
  struct Tries {
    int reached = 0, tried = 0;
  };
  static std::uint64_t key(int node, int grasp) {
    return (std::uint64_t(std::uint32_t(node)) << 32) | std::uint32_t(grasp);
  }
  PerGraspCheckers* per_grasp_;
  const PlacementTree* tree_;
  PlacementVariant variant_;
  double p_accept_;
  int hand_tries_;
  HandFree hand_free_;
  long hand_checks_ = 0;
  std::vector<std::vector<int>> node_grasps_;       // per tree node, in the order cached
  std::unordered_map<std::uint64_t, Tries> tries_;  // per (node, grasp): tries below the node
  std::vector<int> g_;                              // G of the current call
  std::vector<std::uint32_t> in_g_;                 // == stamp_: in G for the current call
  std::vector<char> unusable_;                      // known not usable at q0
  std::uint32_t stamp_ = 0;
};

}  // namespace dmgplace::runtime
