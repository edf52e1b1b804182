#include "dmgplace/runtime/collision/sphere_field_checker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::runtime {
SphereFieldChecker::SphereFieldChecker(const Kinematics& kin, std::vector<formats::LinkSphere> spheres,
                                       std::shared_ptr<const Grid3> sdf, double band, double padding)
    : kin_(&kin), spheres_(std::move(spheres)), allowed_(kin.model().allowed_pairs), band_(band), padding_(padding) {
  if (!sdf) throw Error("SphereFieldChecker", "", "no distance field");
  lo_ = sdf->origin();
  hi_ = sdf->point(sdf->dims()[0] - 1, sdf->dims()[1] - 1, sdf->dims()[2] - 1);
  for (const auto& s : spheres_)
    if (s.link < 0 || std::size_t(s.link) >= kin.model().links.size())
      throw Error("SphereFieldChecker", "spheres", "link index out of range");
  // Queries read only these node-bound copies of the field (the float grid is not kept).
  fine_ = std::make_shared<NodeBoundGrid>(*sdf, 1);
  const auto& d = sdf->dims();
  if ((d[0] - 1) / kCoarseStride >= 1 && (d[1] - 1) / kCoarseStride >= 1 && (d[2] - 1) / kCoarseStride >= 1)
    coarse_ = std::make_shared<NodeBoundGrid>(*sdf, kCoarseStride);
  std::stable_sort(spheres_.begin(), spheres_.end(),
                   [](const formats::LinkSphere& a, const formats::LinkSphere& b) { return a.link < b.link; });
  auto inner = std::make_shared<std::vector<double>>();
  for (const auto& s : spheres_) inner->push_back(inner_radius(kin.model().links[std::size_t(s.link)].collision, s.center));
  inner_ = std::move(inner);
  build_bodies();
}

inline __attribute__((always_inline)) double SphereFieldChecker::coarse_lower_bound(const Eigen::Vector3d& p) const {
  return coarse_ ? coarse_->lower_bound(p) : -1.0;
}

// The fine grid's bound at p from its nearest node: one load where a trilinear sample takes eight
// (four cache lines), and on average tighter than the sample minus its worst-case interpolation
// error (sqrt(3)/2 of a cell): the loss is |p - node| (about half a cell) plus or minus the slope.
inline __attribute__((always_inline)) double SphereFieldChecker::fine_lower_bound(const Eigen::Vector3d& p) const {
  return fine_->lower_bound(p);
}

void SphereFieldChecker::build_bodies() {
  const auto moving = kin_->moving_links();
  bodies_.clear();
  const int robot_end = attached_link_ >= 0 ? attached_begin_ : int(spheres_.size());
  for (int i = 0; i < robot_end;) {
    Body b;
    b.link = spheres_[std::size_t(i)].link;
    b.begin = i;
    while (i < robot_end && spheres_[std::size_t(i)].link == b.link) ++i;
    b.end = i;
    bodies_.push_back(b);
  }
  if (attached_link_ >= 0 && attached_begin_ < int(spheres_.size()))
  {
    Body b;
    b.link = attached_link_;
    b.begin = attached_begin_;
    b.end = int(spheres_.size());
    b.attached = true;
    bodies_.push_back(b);
  }
  const auto& model = kin_->model();
  std::vector<int> parent_joint(model.links.size(), -1);
  for (std::size_t j = 0; j < model.joints.size(); ++j) parent_joint[std::size_t(model.joints[j].child)] = int(j);
  certifiable_ = true;
  for (const auto& j : model.joints) certifiable_ &= !(j.mimic >= 0 && kin_->chain_slot(j.mimic) >= 0);
  for (auto& b : bodies_) {
    b.moving = moving[std::size_t(b.link)];
  }
  for (auto& b : bodies_) {
    // Bounding sphere: centre of the spheres' box, radius reaching every sphere's far side.
    Eigen::AlignedBox3d box;
    for (int i = b.begin; i < b.end; ++i) box.extend(spheres_[std::size_t(i)].center);
    b.center = box.center();
    for (int i = b.begin; i < b.end; ++i)
      b.radius = std::max(b.radius, (spheres_[std::size_t(i)].center - b.center).norm() + spheres_[std::size_t(i)].radius);
    // Reach from each chain joint above: the body's extent in its link frame plus every joint
    // offset on the way up (a prismatic joint's offset grows by its largest travel).
    b.chain.clear();
    double reach = b.center.norm() + b.radius;
    for (int l = b.link, guard = 0; parent_joint[std::size_t(l)] >= 0 && guard <= int(model.joints.size()); ++guard) {
      const int j = parent_joint[std::size_t(l)];
      const Joint& jt = model.joints[std::size_t(j)];
      const bool prismatic = jt.type == JointType::Prismatic;
      if (kin_->chain_slot(j) >= 0) b.chain.push_back({kin_->chain_slot(j), prismatic ? 1.0 : reach, jt.child, jt.axis.normalized(), prismatic});
      reach += jt.origin.translation().norm() + (prismatic ? std::max(std::abs(jt.lower), std::abs(jt.upper)) : 0.0);
      l = jt.parent;
    }
  }
  auto allowed = [&](int a, int b) {
    if (a == b) return true;
    for (auto [x, y] : allowed_)
      if ((x == a && y == b) || (x == b && y == a)) return true;
    return false;
  };
  // Joints above both bodies move them together: only the others change their distance.
  auto relative_moves = [](const Body& a, const Body& b) {
    auto only = [](const Body& x, const Body& y) {
      std::vector<ChainJoint> out;
      for (const auto& c : x.chain)
        if (std::none_of(y.chain.begin(), y.chain.end(), [&](const ChainJoint& d) { return d.slot == c.slot; }))
          out.push_back(c);
      return out;
    };
    return PairMoves{only(a, b), only(b, a)};
  };
  pairs_.clear();
  pair_moves_.clear();
  auto add_pair = [&](std::size_t i, std::size_t j, int table) {
    pairs_.push_back({int(i), int(j), table, bodies_[i].radius + bodies_[j].radius + padding_});
    pair_moves_.push_back(relative_moves(bodies_[i], bodies_[j]));
  };
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    for (std::size_t j = i + 1; j < bodies_.size(); ++j) {
      const Body &a = bodies_[i], &b = bodies_[j];
      if (!a.moving && !b.moving && !a.attached && !b.attached) continue;  // never changes: not our concern
      if (a.attached || b.attached) {
        const int other = a.attached ? b.link : a.link;
        // The object may touch the link holding it and the fingers.
        if (other == attached_link_ || std::find(touching_.begin(), touching_.end(), other) != touching_.end()) continue;
        add_pair(i, j, -1);
        continue;
      }
      if (allowed(a.link, b.link)) continue;
      int table = -1;
      for (std::size_t t = 0; tables_ && t < tables_->size(); ++t) {
        const auto& tt = (*tables_)[t].data;
        if ((tt.link_a == a.link && tt.link_b == b.link) || (tt.link_a == b.link && tt.link_b == a.link)) table = int(t);
      }
      add_pair(i, j, table);
    }
}

SphereFieldChecker::Table::Table(const formats::SelfDistanceTable& t) : data(t) {
  for (int k = 0; k < 2; ++k) inv_step[k] = 1.0 / t.step[std::size_t(k)];
  tenths_mm.reserve(t.distance.size());
  for (float d : t.distance)  // rounded down, one step lower for float rounding
    tenths_mm.push_back(std::uint16_t(std::clamp(std::floor(double(d) * 1e4) - 1.0, 0.0, 65535.0)));
  data.distance.clear();  // kept once, above
}

void SphereFieldChecker::set_self_tables(const std::vector<formats::SelfDistanceTable>& tables) {
  auto out = std::make_shared<std::vector<Table>>();
  const int nl = int(kin_->model().links.size());
  for (const auto& t : tables) {
    Table r(t);
    if (t.link_a < 0 || t.link_b < 0 || t.link_a >= nl || t.link_b >= nl)
      throw Error("SphereFieldChecker", "self tables", "link index out of range");
    for (int k = 0; k < 2; ++k) {
      r.slot[k] = t.joints[std::size_t(k)] >= 0 ? kin_->chain_slot(t.joints[std::size_t(k)]) : -1;
      if (t.joints[std::size_t(k)] >= 0 && r.slot[k] < 0)
        throw Error("SphereFieldChecker", "self tables", "table joint is not driven by this arm chain");
    }
    if (r.slot[0] < 0 || t.count[0] < 1 || t.count[1] < 1 || (r.slot[1] < 0 && t.count[1] != 1) ||
        std::size_t(t.count[0]) * std::size_t(t.count[1]) != t.distance.size())
      throw Error("SphereFieldChecker", "self tables", "table grid and distances disagree");
    out->push_back(std::move(r));
  }
  tables_ = std::move(out);
  build_bodies();
}

SphereFieldChecker SphereFieldChecker::with_attached(AttachedSpheres object) const {
  if (object.link < 0 || std::size_t(object.link) >= kin_->model().links.size())
    throw Error("SphereFieldChecker", "attached object", "link index out of range");
  if (object.centers.size() != object.radii.size())
    throw Error("SphereFieldChecker", "attached object", "centres and radii differ in count");
  SphereFieldChecker c = *this;
  if (c.attached_link_ >= 0) c.spheres_.resize(std::size_t(c.attached_begin_));  // replace a previous object
  c.attached_link_ = object.link;
  c.attached_begin_ = int(c.spheres_.size());
  c.touching_ = std::move(object.touching_links);
  for (std::size_t i = 0; i < object.centers.size(); ++i) c.spheres_.push_back({object.link, object.centers[i], object.radii[i]});
  c.build_bodies();
  return c;
}

SphereFieldChecker SphereFieldChecker::with_kinematics(const Kinematics& kin) const {
  if (&kin.model() != &kin_->model())
    throw Error("SphereFieldChecker", "kinematics", "a different robot model: only joint values outside the chain may differ");
  SphereFieldChecker c = *this;
  c.kin_ = &kin;
  c.build_bodies();  // reaches come from the model (prismatic travel included), rebuilt anyway
  return c;
}

namespace {
// Below this field clearance (metres) a refined certificate also asks the exact primitives: the
// node bound's loss is then a large share of the clearance (tried 0.02-0.2 m on MotionBenchMaker).
constexpr double kExactBelow = 0.05;
}

const std::vector<Eigen::Isometry3d>& SphereFieldChecker::poses_at(const Eigen::VectorXd& q) const {
  thread_local std::vector<Eigen::Isometry3d> poses;
  if (tables_)  // start loading the table nodes while FK runs
    for (const auto& t : *tables_) t.prefetch(q);
  kin_->link_poses(q, poses);
  return poses;
}

SphereCheck SphereFieldChecker::check(const Eigen::VectorXd& q) const { return evaluate(q, poses_at(q), nullptr, 0.0); }

SphereCheck SphereFieldChecker::check(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses) const {
  return evaluate(q, poses, nullptr, 0.0);
}

SphereCheck SphereFieldChecker::check_along(const Eigen::VectorXd& q, const Eigen::VectorXd& direction, double enough) const {
  return evaluate(q, poses_at(q), &direction, enough);
}

SphereCheck SphereFieldChecker::check_along(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses,
                                            const Eigen::VectorXd& direction, double enough) const {
  return evaluate(q, poses, &direction, enough);
}

SphereCheck SphereFieldChecker::evaluate(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses,
                                         const Eigen::VectorXd* dir, double enough) const {
  if (poses.size() != kin_->model().links.size()) throw Error("SphereFieldChecker", "link poses", "one pose per link expected");
  thread_local std::vector<Eigen::Vector3d> body_center, world;
  thread_local std::vector<char> world_done;
  thread_local std::vector<double> body_clear;  // certified mode: each body's clearance
  const bool certify = dir && certifiable_ && enough > 0;  // enough 0: the caller needs no certificate
  body_center.resize(bodies_.size());
  world.resize(spheres_.size());
  world_done.assign(bodies_.size(), 0);
  if (certify) body_clear.assign(bodies_.size(), std::numeric_limits<double>::infinity());
  // World sphere centres of a body, computed at most once per query.
  auto centres = [&](std::size_t bi) {
    if (!world_done[bi]) {
      const Body& b = bodies_[bi];
      const Eigen::Isometry3d& T = poses[std::size_t(b.link)];
      for (int i = b.begin; i < b.end; ++i) world[std::size_t(i)] = T * spheres_[std::size_t(i)].center;
      world_done[bi] = 1;
    }
  };
  SphereCheck out;
  out.min_clearance = band_;
  auto outside = [&](const Eigen::Vector3d& p) { return ((p - lo_).array() < 0).any() || ((hi_ - p).array() < 0).any(); };
  thread_local std::vector<char> body_flagged;  // certified mode: left to the exact layer
  if (certify) body_flagged.assign(bodies_.size(), 0);
  auto cleared = [&](std::size_t bi, double clearance) {
    out.min_clearance = std::min(out.min_clearance, clearance);
    if (certify && !body_flagged[bi]) body_clear[bi] = std::min(body_clear[bi], clearance);
  };
  // All body centres first, their fine-grid nodes requested at once (most misses then overlap).
  for (std::size_t bi = 0; bi < bodies_.size(); ++bi) {
    body_center[bi] = poses[std::size_t(bodies_[bi].link)] * bodies_[bi].center;
    if (bodies_[bi].moving || bodies_[bi].attached) fine_->prefetch(body_center[bi]);
  }
  for (std::size_t bi = 0; bi < bodies_.size(); ++bi) {
    const Body& b = bodies_[bi];
    if (!b.moving && !b.attached) continue;
    if (!outside(body_center[bi])) {
      const double dc = coarse_lower_bound(body_center[bi]) - b.radius - padding_;
      if (dc >= 0) {
        cleared(bi, dc);
        continue;  // cleared from the coarse grid alone
      }
      const double d = fine_lower_bound(body_center[bi]) - b.radius - padding_;
      if (d >= 0) {
        cleared(bi, d);
        continue;  // the whole body is clear
      }
    }
    centres(bi);
    for (int i = b.begin; i < b.end; ++i) fine_->prefetch(world[std::size_t(i)]);
    // Keep going after a hit: every flagged link is listed, so the exact layer can check just those.
    // With exact primitives every sphere of a flagged link is looked at, to name every primitive
    // the link may touch; without, the first flagged sphere settles the link.
    const bool masks = obstacles_ && obstacles_->all_have_bits() && !b.attached;
    std::uint64_t mask = 0;
    bool flagged = false;
    for (int i = b.begin; i < b.end; ++i) {
      const auto& s = spheres_[std::size_t(i)];
      const Eigen::Vector3d& w = world[std::size_t(i)];
      // Outside the grid nothing is known: "maybe in collision", for the exact layer to decide.
      // (Band-clamped far cells are fine: clamping only lowers values, which stays conservative.)
      const bool out_of_grid = outside(w);
      if (!out_of_grid) {
        const double coarse = coarse_lower_bound(w) - s.radius - padding_;
        if (coarse >= 0) {
          cleared(bi, coarse);
          continue;
        }
      }
      const double clearance = out_of_grid ? -1.0 : fine_lower_bound(w) - s.radius - padding_;
      if (clearance >= 0) {
        cleared(bi, clearance);
        continue;
      }
      if (obstacles_) {  // exact, inside the grid or not
        const double distance = obstacles_->distance(w);
        const double exact = distance - s.radius - padding_;
        if (exact >= 0) {
          cleared(bi, exact);
          continue;
        }
        if (inner(i) > 0 && distance < inner(i)) {  // part of the link's solid is inside an obstacle (0: unknown)
          out.environment_free = false;
          out.proven_collision = true;
          return out;
        }
      }
      if (!out_of_grid) out.min_clearance = std::min(out.min_clearance, clearance);
      out.environment_free = false;
      out.outside_grid |= out_of_grid && !obstacles_;
      if (!flagged) {
        flagged = true;
        if (certify) {  // the exact layer certifies this link from its exact distance
          body_flagged[bi] = 1;
          body_clear[bi] = std::numeric_limits<double>::infinity();
        }
        if (b.attached) out.attached_near_env = true;
        else if (out.env_link_count < SphereCheck::kMaxPairs) out.env_links[std::size_t(out.env_link_count++)] = b.link;
        else out.env_overflow = true;
      }
      if (!masks) break;
      mask |= obstacles_->touching(w, s.radius + padding_);
    }
    if (flagged && masks && !out.env_overflow && out.env_links[std::size_t(out.env_link_count - 1)] == b.link)
      out.env_masks[std::size_t(out.env_link_count - 1)] = mask;
  }
  // Certified mode: every clearance (a body's to the scene, a pair's) is a candidate limit on the
  // certificate, first over a cheap static speed (metres per unit of joint motion); the smallest
  // candidates are refined below until the limit is final or the certificate long enough.
  auto speed = [&](const std::vector<ChainJoint>& joints) {
    double v = 0;
    for (const auto& j : joints) v += std::abs((*dir)[j.slot]) * j.reach;
    return v;
  };
  struct Candidate {
    double t;          // how long `clearance` lasts, as far as known
    double clearance;  // metres
    std::size_t index; // body, or pair
    bool pair;
    bool fine;         // the clearance is already sphere by sphere
    int level;         // 0 static speed, 1 local speed, 2 local speed and sphere clearances (final)
    DisplacementBound speed;
  };
  thread_local std::vector<Candidate> cands;
  cands.clear();
  double free_distance = std::numeric_limits<double>::infinity();
  // A clearance lasting past `enough` is not looked at closely (most pairs cost no sqrt): it only
  // proves `enough`, which caps the certificate.
  bool skipped = false;
  for (std::size_t pi = 0; pi < pairs_.size(); ++pi) {
    const Pair& p = pairs_[pi];
    const double rb = p.reach;
    const double d2 = (body_center[std::size_t(p.a)] - body_center[std::size_t(p.b)]).squaredNorm();
    const double v = certify ? speed(pair_moves_[pi].a) + speed(pair_moves_[pi].b) : 0.0;
    const bool certify_this = v > 0;  // (a pair the motion does not move relative needs nothing)
    const double need = certify_this ? enough * v : 0.0;
    if (d2 >= rb * rb) {
      if (certify_this) {
        if (d2 < (rb + need) * (rb + need)) {
          const double gap = std::sqrt(d2) - rb;
          cands.push_back({gap / v, gap, pi, true, false, 0, {}});
        } else {
          skipped = true;
        }
      }
      continue;
    }
    const Body &a = bodies_[std::size_t(p.a)], &b = bodies_[std::size_t(p.b)];
    if (p.table >= 0) {
      const Table& t = (*tables_)[std::size_t(p.table)];
      const double lb = t.lower_bound(q) - padding_;
      if (lb > 0) {
        if (certify_this) {
          // Only the table's joints move the pair relative to each other, at most `slope` each.
          double vt = t.data.slope[0] * std::abs((*dir)[t.slot[0]]);
          if (t.slot[1] >= 0) vt += t.data.slope[1] * std::abs((*dir)[t.slot[1]]);
          if (vt > 0) free_distance = std::min(free_distance, lb / vt);
        }
        continue;
      }
    }
    centres(std::size_t(p.a));
    centres(std::size_t(p.b));
    bool hit = false;
    double gap = std::numeric_limits<double>::infinity();
    for (int i = a.begin; i < a.end && !hit; ++i) {
      const Eigen::Vector3d& wa = world[std::size_t(i)];
      const double ra = spheres_[std::size_t(i)].radius + padding_;
      for (int j = b.begin; j < b.end; ++j) {
        const double r = ra + spheres_[std::size_t(j)].radius;
        const double s2 = (wa - world[std::size_t(j)]).squaredNorm();
        if (s2 < r * r) {
          // The two inner balls overlap: so do the solids (both must have a ball: 0 is unknown).
          const double ia = inner(i), ib = inner(j), in = ia + ib;
          if (ia > 0 && ib > 0 && s2 < in * in) {
            out.self_free = false;
            out.proven_collision = true;
            return out;
          }
          hit = true;
          break;
        }
        if (!certify_this) continue;
        if (s2 < (r + need) * (r + need)) gap = std::min(gap, std::sqrt(s2) - r);
        else skipped = true;
      }
    }
    if (!hit) {
      if (certify_this && std::isfinite(gap)) cands.push_back({gap / v, gap, pi, true, true, 0, {}});
      continue;
    }
    out.self_free = false;
    if (a.attached || b.attached) out.attached_involved = true;
    if (out.pair_count == SphereCheck::kMaxPairs) {
      out.pairs_overflow = true;
      return out;
    }
    out.pairs[std::size_t(out.pair_count++)] = {a.link, b.link};
  }
  // Flagged links and pairs are left out: the exact layer certifies them (link_time, pair_time).
  if (certify) {
    for (std::size_t bi = 0; bi < bodies_.size(); ++bi)
      if ((bodies_[bi].moving || bodies_[bi].attached) && std::isfinite(body_clear[bi])) {
        const double v = speed(bodies_[bi].chain);
        if (v > 0) cands.push_back({body_clear[bi] / v, body_clear[bi], bi, false, false, 0, {}});
      }
    const double limit = std::min(free_distance, enough);
    while (!cands.empty()) {
      auto c = std::min_element(cands.begin(), cands.end(), [](const Candidate& x, const Candidate& y) { return x.t < y.t; });
      if (c->t >= limit || c->level == 2) break;
      if (c->level == 0) {
        c->speed = c->pair ? pair_speed(c->index, poses, body_center, *dir)
                           : joint_speed(bodies_[c->index].chain, poses, body_center[c->index], bodies_[c->index].radius, *dir);
        c->t = c->speed.time_to_move(c->clearance);
        c->level = c->fine ? 2 : 1;
        continue;
      }
      // Sphere by sphere (the bounding spheres, or the coarse grid, gave less).
      double clearance = std::numeric_limits<double>::infinity();
      if (c->pair) {
        const Body &a = bodies_[std::size_t(pairs_[c->index].a)], &b = bodies_[std::size_t(pairs_[c->index].b)];
        centres(std::size_t(pairs_[c->index].a));
        centres(std::size_t(pairs_[c->index].b));
        for (int i = a.begin; i < a.end; ++i)
          for (int j = b.begin; j < b.end; ++j)
            clearance = std::min(clearance, (world[std::size_t(i)] - world[std::size_t(j)]).norm() - spheres_[std::size_t(i)].radius -
                                                spheres_[std::size_t(j)].radius - padding_);
      } else {
        const Body& b = bodies_[c->index];
        centres(c->index);
        for (int i = b.begin; i < b.end; ++i) fine_->prefetch(world[std::size_t(i)]);
        for (int i = b.begin; i < b.end; ++i) {
          const auto& sp = spheres_[std::size_t(i)];
          const Eigen::Vector3d& w = world[std::size_t(i)];
          double sc = std::max(coarse_lower_bound(w), fine_lower_bound(w)) - sp.radius - padding_;
          // Near a surface the node bound's loss is most of the clearance: ask the exact shapes.
          if (obstacles_ && sc < kExactBelow) sc = std::max(sc, obstacles_->distance(w) - sp.radius - padding_);
          clearance = std::min(clearance, sc);
        }
      }
      c->clearance = std::max(clearance, c->clearance);
      c->t = c->speed.time_to_move(c->clearance);
      c->level = 2;
    }
    for (const auto& c : cands) free_distance = std::min(free_distance, c.t);
    if (skipped) free_distance = std::min(free_distance, enough);
    out.free_distance = std::isfinite(free_distance) ? free_distance : 1e9;
  }
  return out;
}

double SphereFieldChecker::link_time(const std::vector<Eigen::Isometry3d>& poses, int link, double gap,
                                     const Eigen::VectorXd& direction) const {
  if (!certifiable_ || gap <= 0) return 0.0;
  for (const Body& b : bodies_)
    if (b.link == link && !b.attached)
      return joint_speed(b.chain, poses, poses[std::size_t(link)] * b.center, b.radius, direction).time_to_move(gap);
  return 0.0;
}

double SphereFieldChecker::pair_time(const std::vector<Eigen::Isometry3d>& poses, int link_a, int link_b, double gap,
                                     const Eigen::VectorXd& direction) const {
  if (!certifiable_ || gap <= 0) return 0.0;
  for (std::size_t pi = 0; pi < pairs_.size(); ++pi) {
    const Body &a = bodies_[std::size_t(pairs_[pi].a)], &b = bodies_[std::size_t(pairs_[pi].b)];
    if (a.attached || b.attached || !((a.link == link_a && b.link == link_b) || (a.link == link_b && b.link == link_a))) continue;
    thread_local std::vector<Eigen::Vector3d> centers;
    centers.resize(bodies_.size());
    centers[std::size_t(pairs_[pi].a)] = poses[std::size_t(a.link)] * a.center;
    centers[std::size_t(pairs_[pi].b)] = poses[std::size_t(b.link)] * b.center;
    return pair_speed(pi, poses, centers, direction).time_to_move(gap);
  }
  return 0.0;
}

DisplacementBound SphereFieldChecker::joint_speed(const std::vector<ChainJoint>& joints,
                                                  const std::vector<Eigen::Isometry3d>& poses, const Eigen::Vector3d& center,
                                                  double radius, const Eigen::VectorXd& dir) const {
  BallMotion m(center, radius);
  for (auto it = joints.rbegin(); it != joints.rend(); ++it) {  // from the top of the chain down
    const Eigen::Isometry3d& T = poses[std::size_t(it->child)];
    const Eigen::Vector3d axis = T.linear() * it->axis;
    if (it->prismatic) m.add_prismatic(axis, dir[it->slot], it->reach);
    else m.add_revolute(axis, T.translation(), dir[it->slot], it->reach);
  }
  return m.bound();
}

DisplacementBound SphereFieldChecker::pair_speed(std::size_t pi, const std::vector<Eigen::Isometry3d>& poses,
                                                 const std::vector<Eigen::Vector3d>& centers, const Eigen::VectorXd& dir) const {
  const Pair& p = pairs_[pi];
  DisplacementBound s = joint_speed(pair_moves_[pi].a, poses, centers[std::size_t(p.a)], bodies_[std::size_t(p.a)].radius, dir);
  s.add(joint_speed(pair_moves_[pi].b, poses, centers[std::size_t(p.b)], bodies_[std::size_t(p.b)].radius, dir));
  return s;
}

}  // namespace dmgplace::runtime
