#pragma once
// The fast collision layer: the robot's (and held object's) spheres against the environment's
// signed distance grid, plus sphere-sphere self-collision for link pairs that are not allowed to
// touch. Conservative by construction: a grid node's value minus the distance to it bounds the
// 1-Lipschitz distance from below (band clamping only lowers values), so it may say "collision"
// near surfaces but never "free" where the spheres touch an obstacle.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/collision/displacement_bound.hpp"
#include "dmgplace/runtime/collision/node_bound_grid.hpp"
#include "dmgplace/runtime/collision/primitive_obstacles.hpp"
#include "dmgplace/runtime/geometry/capsule.hpp"
#include "dmgplace/runtime/geometry/grid3.hpp"
#include "dmgplace/runtime/robot/kinematics_lanes.hpp"

namespace dmgplace::runtime {

// Spheres rigidly attached to one link (e.g. the held object under a grasp), in that link's frame.
struct AttachedSpheres {
  int link = -1;
  std::vector<Eigen::Vector3d> centers;
  std::vector<double> radii;
  std::vector<int> touching_links;  // links it may touch (the fingers)
};

struct SphereCheck {
  static constexpr int kMaxPairs = 16;
  bool environment_free = true;
  bool self_free = true;
  // Link pairs whose spheres overlap (for the exact layer to check just those); when more than
  // kMaxPairs overlap, `pairs_overflow` is set and only a full exact check can tell.
  std::array<std::pair<int, int>, kMaxPairs> pairs{};
  int pair_count = 0;
  bool pairs_overflow = false;
  bool attached_involved = false;  // a flagged pair involves the held object
  // Links whose spheres come too close to the environment or leave the grid (the exact layer
  // checks just those against the scene); `attached_near_env` for the held object.
  std::array<int, kMaxPairs> env_links{};
  // Per flagged link, with exact primitives: bit k set when one of its spheres reaches scene
  // primitive k, so FCL need only test those (0: unknown, test the whole scene).
  std::array<std::uint64_t, kMaxPairs> env_masks{};
  int env_link_count = 0;
  bool env_overflow = false;
  bool attached_near_env = false;
  bool outside_grid = false;  // a sphere left the distance grid: only the exact layer can tell
  // A ball inside a link's solid reaches an exact primitive, or another link's inner ball: the
  // configuration collides, no exact check needed (the rest of this answer is then incomplete).
  bool proven_collision = false;
  double min_clearance = 0;  // smallest proven (distance - radius) seen, metres
  // check_along() only. When free: q + t * direction is free for every t in [0, free_distance]
  // (the spheres cannot move farther than their clearance); 0 when nothing is certified. When
  // links or pairs are flagged (and nothing overflowed or was proven): the same for everything
  // else, the flagged links and pairs left out, for the exact layer to certify (link_time, pair_time).
  double free_distance = 0;
  // The same certificate with every bound isotropic (no directional one, displacement_bound.hpp):
  // a guide to how far a lane check's static widening reaches here (CertifiedMotionValidator's span
  // estimate). At most free_distance.
  double isotropic_distance = 0;
  bool free() const { return environment_free && self_free; }
};

class SphereFieldChecker {
 public:
  // `sdf` is the environment's signed distance in the kinematics' base frame; `band` the value
  // far cells were clamped to (distances at or above it are "at least band").
  SphereFieldChecker(const Kinematics& kin, std::vector<formats::LinkSphere> spheres, std::shared_ptr<const Grid3> sdf,
                     double band, double padding = 0.0);
  // For a scene of exact primitives alone (PrimitiveObstacles::from_scene, at most 64 of them:
  // all_have_bits()), which every check then reads instead of a field: nothing is baked for a
  // new scene. Other scenes: dmgplace::Error.
  SphereFieldChecker(const Kinematics& kin, std::vector<formats::LinkSphere> spheres,
                     std::shared_ptr<const PrimitiveObstacles> obstacles, double padding = 0.0);

  // Exact self-distance tables (from ROBOT.h5): a pair with a table is settled by its proven lower
  // bound where its spheres overlap, instead of being flagged for FCL.
  void set_self_tables(const std::vector<formats::SelfDistanceTable>& tables);

  // The environment's exact primitives, when it is made only of those (PrimitiveObstacles::
  // from_scene): spheres the field leaves undecided are settled by their exact distance. A scene
  // of at most 64 primitives is then checked by exact distances alone, the field left unread
  // (exact_scene()). A checker built without a field keeps such a scene (dmgplace::Error otherwise).
  void set_exact_obstacles(std::shared_ptr<const PrimitiveObstacles> obstacles);
  // Whether a distance field backs the checks (false: exact primitives alone).
  bool has_field() const { return fine_ != nullptr; }

  // A checker for one grasp: same robot and environment (shared, no copy), plus the object.
  SphereFieldChecker with_attached(AttachedSpheres object) const;
  // The same checker posing the robot with `kin` (a copy of this one's kinematics, the same model,
  // other finger joint values); `kin` must outlive the checker.
  SphereFieldChecker with_kinematics(const Kinematics& kin) const;

  SphereCheck check(const Eigen::VectorXd& q) const;
  // check() plus a certified free distance along `direction` (joint space; any length): how long
  // every body's clearance to the scene, and every pair's gap, lasts under a bound on how far the
  // motion can move them (displacement_bound.hpp: static reach, Gronwall, Taylor).
  // `enough`: a certificate this long is all the caller needs (refining stops there); 0 asks for
  // none (then free_distance is 0, and the check costs what check() does).
  SphereCheck check_along(const Eigen::VectorXd& q, const Eigen::VectorXd& direction,
                          double enough = std::numeric_limits<double>::infinity()) const;
  // The same with the link poses at q already computed (Kinematics::link_poses), to share one
  // forward kinematics with the exact layer.
  SphereCheck check(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses) const;
  SphereCheck check_along(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses,
                          const Eigen::VectorXd& direction,
                          double enough = std::numeric_limits<double>::infinity()) const;
  bool is_free(const Eigen::VectorXd& q) const { return check(q).free(); }

  // How long along `direction` (joint space, as check_along) a flagged link keeps an exact
  // clearance `gap` (metres) to the scene, or a flagged pair of links their exact gap: the same
  // speed bounds as the spheres' certificates, over the link's whole body. 0 when the link has no
  // body here (no spheres) or the pair is not one this checker tests.
  double link_time(const std::vector<Eigen::Isometry3d>& poses, int link, double gap,
                   const Eigen::VectorXd& direction) const;
  double pair_time(const std::vector<Eigen::Isometry3d>& poses, int link_a, int link_b, double gap,
                   const Eigen::VectorXd& direction) const;
  // The speed bounds behind link_time and pair_time (time = bound.time_to_move(gap)), for a caller
  // that asks the gap only as far as it needs (bound.displacement(t)); false where those give 0.
  // `velocity` (optional): the link's body's first-order velocity field, for directional bounds
  // (bound.along(velocity.along(n)) for a gap proven along n).
  bool link_speed(const std::vector<Eigen::Isometry3d>& poses, int link, const Eigen::VectorXd& direction,
                  DisplacementBound& bound, BallVelocity* velocity = nullptr) const;
  bool pair_speed(const std::vector<Eigen::Isometry3d>& poses, int link_a, int link_b, const Eigen::VectorXd& direction,
                  DisplacementBound& bound) const;

  // Which of `count` (<= LinkPoseLanesD::kLanes) configurations q[0..count) the spheres alone prove
  // free, in one pass over all of them (lane forward kinematics, sphere centers in SIMD lanes):
  // bit k for q[k]. Proven means every body clear of the scene (the field's bound inside the grid,
  // then the exact primitives when set, anywhere) and every checked pair apart (spheres, or its
  // self-distance table's bound). An unset bit is undecided, never "in collision": check() that
  // configuration. Certificates stay with check_along().
  std::uint32_t free_lanes(const double* const* q, int count = LinkPoseLanesD::kLanes) const;
  // As free_lanes, but bit k says more: every configuration within `reach` (joint-space length)
  // of q[k] along +-direction is free. Each body's test is widened by how far it can move over
  // that length, each pair's (and its table's) by how far they can move relative to each other
  // (the joints moving one and not the other): first by the certificates' static speed (sum over
  // the joints of |direction_j| times the farthest the body gets from joint j's axis); where that
  // leaves a test undecided, by the lanes' own bound (motion_bounds) where smaller. Nothing is
  // proven (0) where speeds are unknown (a mimic joint follows a chain joint) or a static
  // widening passes 1 m.
  std::uint32_t free_lanes_along(const double* const* q, int count, const Eigen::VectorXd& direction,
                                 double reach) const;
  // free_lanes_along's widening, lane by lane, for tests and diagnostics: for every body
  // (link_b = -1) and then every checked pair, how far it can move (a pair: relative to each
  // other) within `reach` along +-direction from q[k], in metres: the smaller of the static bound
  // and the displacement bounds of displacement_bound.hpp (static, Gronwall, Taylor) from the
  // lane's own lever arms, in floats rounded up. The lane check computes the latter only where the
  // static one leaves a test undecided, and takes the largest over the lanes still open. Empty
  // where free_lanes_along proves nothing.
  struct MotionBound {
    int link_a = -1, link_b = -1;
    bool attached = false;  // the held object's body, or a pair with it
    std::array<double, LinkPoseLanesD::kLanes> metres{};
  };
  std::vector<MotionBound> motion_bounds(const double* const* q, int count, const Eigen::VectorXd& direction,
                                         double reach) const;
  // How much free_lanes widens each "free" test (metres) to cover its float rounding, for the
  // kinematics' joint values as they are now.
  double lane_margin() const;

  std::size_t sphere_count() const { return spheres_.size(); }
  const Kinematics& kinematics() const { return *kin_; }

 private:
  // A body is one link's spheres (or the attached object's), with a bounding sphere that is
  // tested first: most bodies are far from obstacles and from each other, so one lookup settles them.
  struct ChainJoint {
    int slot = -1;     // index in q
    double reach = 1;  // metres per unit of this joint: farthest the body gets from its axis (1 if prismatic)
    int child = -1;    // the joint's child link: its frame holds the axis at its origin
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // in the child frame
    bool prismatic = false;
  };
  struct Body {
    int link = -1;
    std::vector<ChainJoint> chain;  // chain joints that move this body, the link's own joint first
    int lever_begin = 0;            // its chain's first lever arm in a query's per-body cache (Pass::levers)
    int begin = 0, end = 0;         // sphere range
    int local = 0;                  // its spheres in pair_spheres_ (offset)
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radius = 0;
    // A long body's capsule (geometry/capsule.hpp), kept for three spheres or more where it is
    // much thinner than the bounding sphere: the lane check's pair tests try it next. inv_len2:
    // 1 / |to - from|^2.
    bool has_capsule = false;
    Capsule capsule;
    double inv_len2 = 0;
    bool moving = false;
    bool attached = false;
  };
  struct Pair {
    int a, b, table = -1;  // body indices, self-distance table or -1
    double reach = 0;      // bounding radii + padding: centers farther apart than this are clear
  };
  // A self-distance table as the hot path reads it: distances as uint16 tenths of a millimetre
  // rounded down (half the memory, so both Panda tables stay in cache), no division per lookup.
  struct Table {
    int slot[2] = {-1, -1};           // q indices of the table's joints; slot[1] = -1 for a 1-D table
    formats::SelfDistanceTable data;  // joints, grid and slopes (its distances are not read here)
    double inv_step[2] = {1, 1};
    std::vector<std::uint16_t> tenths_mm;
    explicit Table(const formats::SelfDistanceTable& t);
    // q: the arm's joint values (only the table's two are read).
    double lower_bound(const double* q) const {
      double loss = 0;
      const std::size_t index = node(q, &loss);
      return 1e-4 * double(tenths_mm[index]) - loss;
    }
    double lower_bound(const Eigen::VectorXd& q) const { return lower_bound(q.data()); }
    // How fast the bound can fall moving along joint-space direction `dir` (by slot): the slopes
    // times the table's joints' rates (the bound is Lipschitz in its joints with those slopes).
    double speed(const double* dir) const {
      double v = 0;
      for (int k = 0; k < 2; ++k)
        if (slot[k] >= 0) v += data.slope[std::size_t(k)] * std::abs(dir[slot[k]]);
      return v;
    }
    // Bit k set where lower_bound(q[k]) > padding, for 8 configurations in SIMD lanes (defined
    // in sphere_lanes.cpp, its only user; `wide` as in free_lanes_body).
    std::uint32_t apart_lanes(const double* const* q, double padding, bool wide) const;
    // Start loading q's node before FK needs the cache (the lookup comes after it).
    void prefetch(const double* q) const { __builtin_prefetch(tenths_mm.data() + node(q, nullptr)); }
    void prefetch(const Eigen::VectorXd& q) const { prefetch(q.data()); }
    // Nearest node to q's table joints, clamped; `loss` (if given): the slope bound to get there.
    std::size_t node(const double* q, double* loss) const {
      std::size_t index = 0;
      for (int k = 0; k < 2; ++k) {
        const double x = slot[k] >= 0 ? q[slot[k]] : 0.0;
        const double u = (x - data.lower[std::size_t(k)]) * inv_step[k];
        const long i = !(u > 0) ? 0 : std::min(long(std::min(u, 1e9) + 0.5), long(data.count[std::size_t(k)]) - 1);
        if (loss)
          *loss += data.slope[std::size_t(k)] *
                   std::abs(x - (data.lower[std::size_t(k)] + double(i) * data.step[std::size_t(k)]));
        index = index * std::size_t(data.count[std::size_t(k)]) + std::size_t(i);
      }
      return index;
    }
  };
  void check_and_sort_spheres();  // the constructors' common part, then build_bodies
  void build_bodies();
  // build_bodies' steps (sphere_field_checker.cpp).
  void group_bodies();
  void shape_body(Body& b) const;
  void chain_body(Body& b, const std::vector<int>& parent_joint);
  void build_pair_spheres();
  void build_pairs();
  void build_static_reach();
  struct Pass;  // one query's passes: environment, self pairs, certificate (src/collision/sphere_check_pass.hpp)
  SphereCheck evaluate(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses,
                       const Eigen::VectorXd* direction, double enough) const;
  const std::vector<Eigen::Isometry3d>& poses_at(const Eigen::VectorXd& q) const;  // thread-local FK
  // Joints moving one body of a pair relative to the other (those above both move them together).
  struct PairMoves {
    std::vector<ChainJoint> a, b;
    std::vector<int> a_at, b_at;  // where each of a, b sits in its body's chain (lever arms cached per body)
  };
  static PairMoves relative_moves(const Body& a, const Body& b);
  bool certifiable_ = true;  // false when a mimic joint follows a chain joint (speeds unknown)
  const Kinematics* kin_;
  std::vector<formats::LinkSphere> spheres_;  // robot + attached, link frames, grouped by body
  // spheres_ as free_lanes reads them: center and radius in floats, each already in all 8 lanes
  // (an operand load costs less than converting and broadcasting per use). Built with the bodies.
  struct alignas(32) LaneSphere {
    float x[LinkPoseLanesD::kLanes], y[LinkPoseLanesD::kLanes], z[LinkPoseLanesD::kLanes], r[LinkPoseLanesD::kLanes];
  };
  // The bodies as free_lanes places them: per body the link whose lane pose carries it, its
  // center and capsule there; per sphere its LaneSphere there. `framed`: each body in its link's
  // lane frame (Kinematics::Lanes::frame), so FK skips the links no chain joint moves; valid while
  // the kinematics' lanes().version is framed_version_. `own`: in the link's own frame, for a
  // kinematics whose set values changed since (valid for any). Built with the bodies.
  struct LaneBodies {
    std::vector<int> link;
    std::vector<Eigen::Vector3d> center;
    std::vector<Capsule> capsule;
    std::vector<LaneSphere> spheres;
  };
  LaneBodies framed_, own_;
  std::uint64_t framed_version_ = 0;
  // free_lanes' view for the kinematics as they are now.
  const LaneBodies& lane_bodies() const { return kin_->lanes().version == framed_version_ ? framed_ : own_; }
  void build_lane_bodies();
  // spheres_ again for pair_contact, per body in its link frame: x, y, z and radius, four arrays of
  // the body's sphere count rounded up to 4 (spare lanes far away, radius 0). Built with the bodies.
  std::vector<double> pair_spheres_;
  static int local_width(const Body& b) { return (b.end - b.begin + 3) & ~3; }
  // A body pair's first overlapping spheres (padding_ added once), in the order the scalar loop
  // visits them (a's spheres, then b's): the global sphere indices and their centers' squared
  // distance, or i = -1. `cb`: b's bounding-sphere center in the world.
  struct PairContact {
    int i = -1, j = -1;
    double s2 = 0;
  };
  PairContact pair_contact(const Pair& p, const Eigen::Isometry3d& Ta, const Eigen::Isometry3d& Tb,
                           const Eigen::Vector3d& cb) const;
  template <bool Wide>
  static PairContact pair_contact_body(const SphereFieldChecker& c, const Pair& p, const Eigen::Isometry3d& Ta,
                                       const Eigen::Isometry3d& Tb, const Eigen::Vector3d& cb);
  static PairContact pair_contact_avx2(const SphereFieldChecker& c, const Pair& p, const Eigen::Isometry3d& Ta,
                                       const Eigen::Isometry3d& Tb, const Eigen::Vector3d& cb);
  // A body's displacement over free_lanes_along's reach from each lane's own lever arms
  // (src/collision/sphere_lane_motion.hpp).
  struct LaneMotion;
  // free_lanes_along's static widening: per body, then per pair (false: past 1 m somewhere).
  bool static_widening(const Eigen::VectorXd& direction, double reach, std::vector<float>& widen) const;
  // The static speeds along `direction` (metres per unit of joint motion): each body's (its chain
  // reaches), then each pair's relative one. Every check and lane check of one motion asks for the
  // same direction, so this thread's last answer is kept (for this body set: id_).
  const std::vector<double>& static_speeds(const Eigen::VectorXd& direction) const;
  std::uint64_t id_ = 0;  // a new one whenever the bodies are built (build_bodies)
  // free_lanes' body, compiled for AVX2 + FMA and for the portable baseline (one per path).
  // `widen`: per body then per pair (bodies_.size() + pairs_.size() floats), metres added to
  // what each test needs (free_lanes_along's static bounds); null: none. `motion` (with widen):
  // a body whose bounding sphere the static widening leaves undecided is widened by its lanes'
  // own bound instead, where smaller.
  static std::uint32_t free_lanes_avx2(const SphereFieldChecker& c, const double* const* q, int count,
                                       const float* widen, const LaneMotion* motion);
  static std::uint32_t free_lanes_portable(const SphereFieldChecker& c, const double* const* q, int count,
                                           const float* widen, const LaneMotion* motion);
  // `wide`: a vector of lanes is one register (AVX2), so masks are ORed and turned into bits once;
  // the portable build compares lane by lane, where bits per test cost less.
  static std::uint32_t free_lanes_body(const SphereFieldChecker& c, const double* const* q, int count,
                                       const float* widen, const LaneMotion* motion, bool wide);
  struct LanePass;  // free_lanes_body's query: environment, then self pairs (src/collision/sphere_lane_pass.hpp)
  // free_lanes works in floats: lanes whose body centers stay within lane_limit_ metres of the
  // origin on every axis, every test that can say "free" widened by lane_margin() metres, which
  // bounds the rounding there: lane_rounding_ for the steps after the poses (set with the robot's
  // bodies and the scene, set_lane_bounds) and the float poses' own error bound (twice for a
  // self pair's tests: one per body).
  void set_lane_bounds();
  double lane_limit_ = 0, lane_rounding_ = 0;
  // A capsule test's own rounding on top (kernels::near_segment), for points and segment ends of
  // bodies whose centers are within lane_limit_.
  double capsule_rounding_ = 0;
  // PrimitiveObstacles::float_error for points within lane_limit_: the scalar passes' exact
  // distances in float lanes (Pass::exact_distances) are lower bounds by this much.
  double exact_float_error_ = 0;
  std::vector<Body> bodies_;
  double reach_ = 0;                   // no sphere gets farther than this from the model root's origin
  double link_reach_ = 0;              // nor from its own link's origin
  std::vector<Pair> pairs_;            // body pairs checked for self-collision
  std::vector<PairMoves> pair_moves_;  // per pair
  // static_speeds as one product: a row per body, then per pair (the pair's relative joints), a
  // column per chain joint (its slot in q), each entry the sum of that joint's reaches in the row.
  Eigen::MatrixXd static_reach_;
  int lever_count_ = 0;                               // chain joints summed over the bodies
  std::shared_ptr<const std::vector<Table>> tables_;  // shared by every per-grasp copy
  // Every `kCoarseStride`-th node of the distance grid: small enough to stay in cache, and with
  // a nearest-node bound (value - distance to the node, 1-Lipschitz) it clears most bodies in one
  // load instead of a trilinear lookup that misses the cache.
  static constexpr int kCoarseStride = 4;
  std::shared_ptr<const NodeBoundGrid> coarse_, fine_;  // shared by every per-grasp copy
  double coarse_lower_bound(const Eigen::Vector3d& p) const;
  double fine_lower_bound(const Eigen::Vector3d& p) const;
  double fine_cell_lower_bound(const Eigen::Vector3d& p) const;
  double fine_upper_bound(const Eigen::Vector3d& p) const;
  std::vector<std::pair<int, int>> allowed_;             // link pairs
  std::vector<int> touching_;                            // links the attached object may touch
  std::shared_ptr<const PrimitiveObstacles> obstacles_;  // null unless the scene is all primitives
  // A few primitives (at most 64, as the lanes' reach masks hold): their exact distances, in
  // cache and with no cell loss or band, cost less than the field's loads (measured on bench-mbm's
  // bookshelf median problems: docs/perf-log.md), so the scalar passes read no field.
  bool exact_scene() const { return obstacles_ && obstacles_->all_have_bits(); }
  // Per robot sphere (link frame, in spheres_ order): the largest ball around its center inside
  // the link's collision geometry, 0 when the center is outside it. Held objects have none.
  std::shared_ptr<const std::vector<double>> inner_;
  double inner(int sphere) const { return std::size_t(sphere) < inner_->size() ? (*inner_)[std::size_t(sphere)] : 0.0; }
  double band_, padding_;
  Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();  // grid bounds (none: zero)
  int attached_link_ = -1;  // link carrying the attached object, -1 when none
  int attached_begin_ = 0;  // first sphere of the attached object
};

}  // namespace dmgplace::runtime
