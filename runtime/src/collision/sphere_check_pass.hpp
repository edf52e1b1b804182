#pragma once
// One SphereFieldChecker query (check, check_along) as three passes over per-thread scratch, one
// file each: the environment (every body against the scene: sphere_environment_pass.cpp), the
// self pairs (sphere_self_pass.cpp) and, for check_along, the certificate
// (sphere_certificate_pass.cpp). The passes share the query's sphere centers, computed at most
// once per body. Private to the runtime.
#include <limits>
#include <vector>

#include "dmgplace/runtime/collision/sphere_field_checker.hpp"

namespace dmgplace::runtime {

inline __attribute__((always_inline)) double SphereFieldChecker::coarse_lower_bound(const Eigen::Vector3d& p) const {
  return coarse_ ? coarse_->lower_bound(p) : -1.0;
}

// The fine grid's bound at p from its nearest node: one load where a trilinear sample takes eight
// (four cache lines), and on average tighter than the sample minus its worst-case interpolation
// error (sqrt(3)/2 of a cell): the loss is |p - node| (about half a cell) plus or minus the slope.
inline __attribute__((always_inline)) double SphereFieldChecker::fine_lower_bound(const Eigen::Vector3d& p) const {
  return fine_->lower_bound(p);
}

inline double SphereFieldChecker::fine_cell_lower_bound(const Eigen::Vector3d& p) const {
  return fine_->cell_lower_bound(p);
}

inline __attribute__((always_inline)) double SphereFieldChecker::fine_upper_bound(const Eigen::Vector3d& p) const {
  return fine_->upper_bound(p);
}

struct SphereFieldChecker::Pass {
  // A clearance (a body's to the scene, a pair's gap) that limits the certificate, refined in
  // levels until its limit is final or beyond what the caller needs.
  struct Candidate {
    double t;           // how long `clearance` lasts, as far as known
    double clearance;   // metres
    std::size_t index;  // body, or pair
    bool pair;
    bool fine;  // the clearance is already sphere by sphere
    int level;  // 0 static speed, 1 local speed, 2 local speed and sphere clearances (final
                // unless `directional`)
    DisplacementBound speed;
    bool exact_center = false;  // a body's bounding sphere was measured against the exact primitives
    bool directional = false;   // level 2 but short of the limit: a directional time may raise it
  };
  // Reused by every query of a thread (sized per query): no allocation once warm.
  struct Scratch {
    std::vector<Eigen::Vector3d> body_center, world;
    // Per body, what this query has done for it (BodyFlag bits): one clear per query.
    std::vector<std::uint8_t> body_flags;
    std::vector<double> body_clear;  // certified mode: each body's clearance to the scene
    std::vector<Candidate> cands;
    std::vector<double> times;  // cands' t, packed: the certificate's smallest-first scan reads only these
    std::vector<std::pair<double, int>> exact_order;  // a body's spheres to ask the exact shapes: field bound, sphere
    // Certified mode: what the environment pass read for a body's spheres (kBoundsRead), so
    // the certificate's sphere-by-sphere refinement does not read it again. Per sphere: the
    // coarse and fine node bounds and the exact primitives' distance, NaN where not read.
    // In exact scenes sphere_exact holds every sphere of a body once it is kDistances
    // (exact_distances), in any mode.
    std::vector<double> sphere_coarse, sphere_fine, sphere_exact;
    std::vector<double> body_exact;  // exact scenes: body_distances()
    // Certified mode: each sphere's gap to the scene as far as the certificate's sphere-by-sphere
    // refinement read it (a lower bound), for the body's directional time.
    std::vector<double> sphere_gap;
    // Certified mode, filled on demand: chain joints' world axes and origins (by slot), and each
    // body's lever arms about its chain joints (Body::lever_begin), shared by the body's bound
    // and its pairs'.
    std::vector<Eigen::Vector3d> slot_axis, slot_origin, lever;
    std::vector<double> lever_norm;
    std::vector<char> slot_done;
  };
  static Scratch& thread_scratch();  // this thread's
  enum BodyFlag : std::uint8_t {
    kWorld = 1,       // s.world holds its spheres (centers())
    kDistances = 2,   // s.sphere_exact holds its spheres' exact distances (exact_distances())
    kBoundsRead = 4,  // certified mode: the environment pass kept what it read for its spheres
    kLevers = 8,      // certified mode: its lever arms are in s.lever (levers())
    kFlagged = 16,    // certified mode: left to the exact layer
  };
  bool has(std::size_t bi, BodyFlag f) const { return (s.body_flags[bi] & f) != 0; }
  void mark(std::size_t bi, BodyFlag f) { s.body_flags[bi] |= f; }

  Pass(const SphereFieldChecker& checker, const Eigen::VectorXd* q, const std::vector<Eigen::Isometry3d>& poses,
       const Eigen::VectorXd* dir, double enough);

  // Each returns false when the answer is final (a proven collision, or more pairs than fit).
  bool environment();
  bool body_clear(std::size_t bi, bool exact);  // environment's steps
  bool environment_spheres(std::size_t bi, bool exact);
  void flag_environment_link(std::size_t bi);  // (once per body and query)
  bool self_pairs();
  enum class PairSpheres { Apart, Touching, ProvenCollision };
  PairSpheres pair_spheres(const Pair& p, double need, double& gap, bool& beyond);  // self_pairs' step
  // self_pairs' verdicts on an overlapping sphere pair (global indices, centers s2 apart): a
  // collision proven by the spheres' inner balls (out says so); the body pair left to the exact
  // layer (out.pairs_overflow when more pairs than fit).
  bool proven_overlap(int i, int j, double s2);
  void flag(const Body& a, const Body& b);
  void certificate();  // out.free_distance

  // How far a body's bounding sphere, or a pair's two, can move along dir (displacement_bound.hpp),
  // from lever arms cached per body. body_center of the bodies asked about must be set.
  DisplacementBound body_speed(std::size_t bi, BallVelocity* velocity = nullptr) {
    return ball_speed(bi, c.bodies_[bi].chain, nullptr, velocity);
  }
  DisplacementBound pair_speed(std::size_t pi) {
    const Pair& p = c.pairs_[pi];
    const PairMoves& m = c.pair_moves_[pi];
    DisplacementBound v = ball_speed(std::size_t(p.a), m.a, m.a_at.data());
    v.add(ball_speed(std::size_t(p.b), m.b, m.b_at.data()));
    return v;
  }
  // A body's bounding ball moved by `joints` (a subset of its chain, in chain order; `at`: their
  // places in it, null for the whole chain). `velocity` (optional): its first-order velocity field.
  DisplacementBound ball_speed(std::size_t bi, const std::vector<ChainJoint>& joints, const int* at,
                               BallVelocity* velocity = nullptr);
  void levers(std::size_t bi);
  // A body's time from its spheres' directional bounds against the primitives (exact scenes only).
  double directional_time(const Candidate& cand, double limit);
  // A body's smallest sphere gap to the scene, each sphere's into s.sphere_gap: from the exact
  // primitives (exact_scene()), or from the field with the primitives where its bounds fall
  // short of lasting `limit`. centers() of the body must be set.
  double pair_sphere_gap(const Pair& p);  // certificate's step for a pair
  double exact_sphere_gaps(std::size_t bi);
  double field_sphere_gaps(const Candidate& cand, double limit);
  // A body's candidate measured by its bounding sphere against the exact primitives (once; where
  // the field has clamped at its band that proves more): raises its clearance and time.
  void exact_center_bound(Candidate& k, double limit);
  // A sphere's exact distance to the scene, as the environment pass read it or now.
  double exact_distance(std::size_t bi, int sphere);
  // Exact scenes: a lower bound on each of a body's spheres' distances to the scene, all at once
  // (PrimitiveObstacles::distances, float lanes, less their rounding bound exact_float_error_),
  // into s.sphere_exact; at most once per query.
  void exact_distances(std::size_t bi);
  // The same for every body's bounding-sphere center, into s.body_exact.
  void body_distances();
  template <class Point>
  void distances_of(int count, Point point, double* out) const;

  // T p as R p + t: Eigen multiplies an Isometry3d's whole 4x4 matrix into (p, 1).
  static Eigen::Vector3d moved(const Eigen::Isometry3d& T, const Eigen::Vector3d& p) {
    return T.linear() * p + T.translation();
  }
  // World sphere centers of a body, computed at most once per query.
  void centers(std::size_t bi) {
    if (has(bi, kWorld)) return;
    const Body& b = c.bodies_[bi];
    const Eigen::Isometry3d& T = poses[std::size_t(b.link)];
    for (int i = b.begin; i < b.end; ++i) s.world[std::size_t(i)] = moved(T, c.spheres_[std::size_t(i)].center);
    mark(bi, kWorld);
  }
  void candidate(double t, double clearance, std::size_t index, bool pair, bool fine) {
    s.cands.push_back({t, clearance, index, pair, fine, 0, {}});
    s.times.push_back(t);
  }
  void cleared(std::size_t bi, double clearance) {
    out.min_clearance = std::min(out.min_clearance, clearance);
    if (certify && !has(bi, kFlagged)) s.body_clear[bi] = std::min(s.body_clear[bi], clearance);
  }
  // A cheap static speed (metres per unit of joint motion along dir, from the chain reaches) of
  // body bi, or of pair pi (index bodies + pi): static_speeds, kept per direction. The pointer
  // holds for the pass: nothing in a pass asks about another direction.
  double static_speed(std::size_t index) {
    if (!speeds) speeds = c.static_speeds(*dir).data();
    return speeds[index];
  }
  const double* speeds = nullptr;
  bool outside(const Eigen::Vector3d& p) const {
    return ((p - c.lo_).array() < 0).any() || ((c.hi_ - p).array() < 0).any();
  }

  const SphereFieldChecker& c;
  const Eigen::VectorXd* q;  // null for a speed query (link_time, pair_time): no self pairs then
  const std::vector<Eigen::Isometry3d>& poses;
  const Eigen::VectorXd* dir;
  const double enough;
  const bool certify;  // a certificate is asked for and can be had
  Scratch& s;
  SphereCheck out;
  // The certificate's bound from pairs settled by their self-distance tables.
  double table_limit = std::numeric_limits<double>::infinity();
  bool skipped = false;  // a clearance lasted past `enough` unexamined: it caps the certificate
};

}  // namespace dmgplace::runtime
