#pragma once
// The exact collision layer (FCL): the robot's collision primitives and meshes, the held object's
// mesh attached at its grasp, and the environment's exact geometry (primitives, triangle BVHs, an
// octree for scan points). Used where the fast layer cannot decide and to validate every path.
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::runtime {

// One mesh's FCL bounding-volume hierarchy, built once and shared by every checker that attaches
// it (one per grasp), so a per-grasp checker costs a copy of a few pointers, not a BVH build.
class CollisionMesh {
 public:
  explicit CollisionMesh(const TriMesh& mesh);
  struct Impl;
  std::shared_ptr<const Impl> impl;
};

struct ExactCheck {
  bool environment_free = true;
  bool self_free = true;
  std::string contact;  // "link_a / obstacle_b" of the first collision found
  bool free() const { return environment_free && self_free; }
};

// Where two links' meshes were closest: their parts and a triangle of each (-1: not meshes).
struct LinkWitness {
  int part_a = -1, tri_a = -1, part_b = -1, tri_b = -1;
};

class ExactChecker {
 public:
  // Scene geometry in the kinematics' base frame. `scan_resolution` sizes the octree cells. Mesh
  // BVHs have OBB nodes: FCL has a closed-form OBB for a box, cylinder or sphere obstacle, where
  // OBBRSS nodes (MoveIt's) make it fit one by eigen-decomposition on every query.
  ExactChecker(const Kinematics& kin, const Scene& environment, double scan_resolution = 0.01);
  ~ExactChecker();
  ExactChecker(const ExactChecker&);
  ExactChecker& operator=(const ExactChecker&) = delete;

  // A checker for one grasp: shares robot and environment geometry, adds the object mesh on `link`
  // at `object_in_link`; it may touch `touching_links` (fingers). Contact with the support is not
  // exempt: placements are checked with the object lifted a little above it.
  ExactChecker with_attached(const TriMesh& object, int link, const Eigen::Isometry3d& object_in_link,
                             std::vector<int> touching_links) const;
  ExactChecker with_attached(const CollisionMesh& object, int link, const Eigen::Isometry3d& object_in_link,
                             std::vector<int> touching_links) const;

  // The same checker posing the robot with `kin`: a copy of this one's kinematics (the same
  // model) with other finger joint values. `kin` must outlive the checker.
  ExactChecker with_kinematics(const Kinematics& kin) const;
  // The same robot (its geometry shared, not rebuilt) in another scene.
  ExactChecker with_scene(const Scene& environment, double scan_resolution = 0.01) const;

  // The listed links' geometry alone at the given poses (world), against the environment: a hand
  // without its arm, for instance.
  bool links_free(const std::vector<std::pair<int, Eigen::Isometry3d>>& link_poses) const;
  // The mesh alone at `pose` (world) against the environment; `contact` names the obstacle hit.
  bool mesh_free(const CollisionMesh& mesh, const Eigen::Isometry3d& pose, std::string* contact = nullptr) const;

  ExactCheck check(const Eigen::VectorXd& q) const;
  // Just these links (and the held object when `object`) against the environment, the links at
  // `poses` (Kinematics::link_poses at q, shared with the sphere layer that flagged them).
  // `masks` (optional, per link): bit k set names the scene's k-th shape (objects, then their
  // shapes, in order) as the only ones that link can touch; 0 means any.
  bool links_environment_free(const std::vector<Eigen::Isometry3d>& poses, const int* links, int count, bool object,
                              const std::uint64_t* masks = nullptr) const;
  // Self-collision of just these link pairs (the ones the sphere layer flagged), links at `poses`.
  bool link_pairs_free(const std::vector<Eigen::Isometry3d>& poses, const std::pair<int, int>* pairs, int count) const;
  bool is_free(const Eigen::VectorXd& q) const { return check(q).free(); }
  // Every pair of links (smaller index first) whose geometry collides at `poses`, among the pairs
  // the model does not allow to touch, whether this chain moves them or not.
  std::vector<std::pair<int, int>> colliding_link_pairs(const std::vector<Eigen::Isometry3d>& poses) const;
  // Smallest distance between two links' collision geometry at q (0 when they touch). `witness`
  // (optional): where it was found, for link_distance_within at nearby configurations.
  double link_distance(const Eigen::VectorXd& q, int link_a, int link_b, LinkWitness* witness = nullptr) const;
  // min(link_distance(q, ...), attained), where `attained` is a distance two points of the links
  // are known to have at q (an upper bound); cheaper the tighter it is. The witness is set only
  // where a pair closer than `attained` was found.
  double link_distance_below(const Eigen::VectorXd& q, int link_a, int link_b, double attained,
                             LinkWitness* witness = nullptr) const;
  // A proven lower bound of link_distance(q, ...) at most `tolerance` below it (0: exactly it).
  // The closest triangles of nearby configurations (`near`, from link_distance) bound the distance
  // from above: within `tolerance` of the links' convex hulls' gap (GJK, from below) that gap is
  // returned; otherwise FCL's exact distance, started from that bound. `witness` (optional): the
  // closest pair seen, for the configurations next to q.
  double link_distance_within(const Eigen::VectorXd& q, int link_a, int link_b, double tolerance,
                              const std::vector<LinkWitness>& near, LinkWitness* witness = nullptr) const;
  // Proven clearances at `poses` for certificates (convex_gap: GJK's dual bound on primitives and
  // on link meshes' convex hulls, Shape::hull): of `link` to every scene shape (a certificate must
  // hold against all of them), and between two links. Lower bounds of the true clearances; a value
  // <= 0 means touching or undecided (a hull can touch where its mesh does not): ask
  // links_environment_free / link_pairs_free. The scene's shapes must be primitives (a mesh or
  // the scan answers 0), and a link mesh needs its hull (0 without). A value >= `enough` says only
  // that the clearance is at least `enough` (a caller asking for a sign passes 0 and stops early).
  double link_environment_gap(const std::vector<Eigen::Isometry3d>& poses, int link,
                              double enough = std::numeric_limits<double>::infinity()) const;
  double link_pair_gap(const std::vector<Eigen::Isometry3d>& poses, int link_a, int link_b,
                       double enough = std::numeric_limits<double>::infinity()) const;
  // How long `link` keeps clear of the scene along a motion, shape by shape, up to `enough_time`:
  // each scene shape's gap g and the unit direction n it was proven along (convex_gap's
  // `separation`) go to time(g, n), and the smallest answer is returned (0 when a gap is not
  // positive; the scene and link shapes as link_environment_gap needs). reach(t): how far any
  // point of the link may move within t, in any direction: shapes are visited nearest bounding
  // ball first, and one farther than that from the smallest time so far cannot end it sooner. A
  // gap is proven only up to `enough_gap` (GJK stops there) unless its time then falls short of
  // `enough_time`.
  double link_environment_time(const std::vector<Eigen::Isometry3d>& poses, int link, double enough_gap,
                               double enough_time,
                               const std::function<double(double gap, const Eigen::Vector3d& n)>& time,
                               const std::function<double(double t)>& reach) const;
  // Whether those gaps can be had: the scene all primitives, every link shape a primitive or a mesh
  // with its hull.
  bool gaps_are_cheap() const;
  // Whether some link shape is a mesh: FCL's test of a primitive link costs less than its gap.
  bool links_have_meshes() const;

  // Exact checks of a and of the segment to b at the states segment_valid (segment_check.hpp) visits.
  bool segment_free(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution) const;

  const Kinematics& kinematics() const { return *kin_; }

  struct Impl;  // FCL objects; defined in the .cpp so FCL headers stay out of ours

 private:
  const Kinematics* kin_;
  std::shared_ptr<const Impl> impl_;
};

}  // namespace dmgplace::runtime
