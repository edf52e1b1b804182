#include "dmgplace/runtime/collision/sphere_field_checker.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "dmgplace/formats/error.hpp"
#include "sphere_check_pass.hpp"

namespace dmgplace::runtime {
SphereFieldChecker::SphereFieldChecker(const Kinematics& kin, std::vector<formats::LinkSphere> spheres,
                                       std::shared_ptr<const Grid3> sdf, double band, double padding)
    : kin_(&kin), spheres_(std::move(spheres)), allowed_(kin.model().allowed_pairs), band_(band), padding_(padding) {
  if (!sdf) throw Error("SphereFieldChecker", "", "no distance field");
  lo_ = sdf->origin();
  hi_ = sdf->point(sdf->dims()[0] - 1, sdf->dims()[1] - 1, sdf->dims()[2] - 1);
  // Queries read only these node-bound copies of the field (the float grid is not kept).
  fine_ = std::make_shared<NodeBoundGrid>(*sdf, 1);
  const auto& d = sdf->dims();
  if ((d[0] - 1) / kCoarseStride >= 1 && (d[1] - 1) / kCoarseStride >= 1 && (d[2] - 1) / kCoarseStride >= 1)
    coarse_ = std::make_shared<NodeBoundGrid>(*sdf, kCoarseStride);
  check_and_sort_spheres();
}

// No band: exact distances are not clamped (it only seeds SphereCheck::min_clearance here).
SphereFieldChecker::SphereFieldChecker(const Kinematics& kin, std::vector<formats::LinkSphere> spheres,
                                       std::shared_ptr<const PrimitiveObstacles> obstacles, double padding)
    : kin_(&kin), spheres_(std::move(spheres)), allowed_(kin.model().allowed_pairs), band_(1e9), padding_(padding) {
  if (!obstacles || !obstacles->all_have_bits())
    throw Error("SphereFieldChecker", "scene",
                "without a distance field the scene must be at most 64 exact primitives");
  check_and_sort_spheres();
  set_exact_obstacles(std::move(obstacles));
}

void SphereFieldChecker::check_and_sort_spheres() {
  for (const auto& s : spheres_)
    if (s.link < 0 || std::size_t(s.link) >= kin_->model().links.size())
      throw Error("SphereFieldChecker", "spheres", "link index out of range");
  std::stable_sort(spheres_.begin(), spheres_.end(),
                   [](const formats::LinkSphere& a, const formats::LinkSphere& b) { return a.link < b.link; });
  auto inner = std::make_shared<std::vector<double>>();
  for (const auto& s : spheres_)
    inner->push_back(inner_radius(kin_->model().links[std::size_t(s.link)].collision, s.center));
  inner_ = std::move(inner);
  build_bodies();
}

// The bodies and everything derived from them, in this order: bodies (bounding spheres, capsules,
// chains), their lane placements and lane bounds, pair spheres, lever offsets, pairs, reaches.
void SphereFieldChecker::build_bodies() {
  static std::atomic<std::uint64_t> next_id{0};
  id_ = ++next_id;
  group_bodies();
  const auto& model = kin_->model();
  reach_ = link_reach_ = 0;
  std::vector<int> parent_joint(model.links.size(), -1);
  for (std::size_t j = 0; j < model.joints.size(); ++j) parent_joint[std::size_t(model.joints[j].child)] = int(j);
  certifiable_ = true;
  for (const auto& j : model.joints) certifiable_ &= !(j.mimic >= 0 && kin_->chain_slot(j.mimic) >= 0);
  for (auto& b : bodies_) {
    shape_body(b);
    chain_body(b, parent_joint);
  }
  build_lane_bodies();
  set_lane_bounds();
  build_pair_spheres();
  lever_count_ = 0;
  for (auto& b : bodies_) {
    b.lever_begin = lever_count_;
    lever_count_ += int(b.chain.size());
  }
  build_pairs();
  build_static_reach();
}

// One body per link's run of spheres (spheres_ is sorted by link), then the attached object's.
void SphereFieldChecker::group_bodies() {
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
  if (attached_link_ >= 0 && attached_begin_ < int(spheres_.size())) {
    Body b;
    b.link = attached_link_;
    b.begin = attached_begin_;
    b.end = int(spheres_.size());
    b.attached = true;
    bodies_.push_back(b);
  }
  for (auto& b : bodies_) b.moving = moving[std::size_t(b.link)];
}

void SphereFieldChecker::shape_body(Body& b) const {
  // Bounding sphere: center of the spheres' box, radius reaching every sphere's far side.
  Eigen::AlignedBox3d box;
  for (int i = b.begin; i < b.end; ++i) box.extend(spheres_[std::size_t(i)].center);
  b.center = box.center();
  for (int i = b.begin; i < b.end; ++i)
    b.radius =
        std::max(b.radius, (spheres_[std::size_t(i)].center - b.center).norm() + spheres_[std::size_t(i)].radius);
  // A capsule only for three spheres or more, where it is well under the bounding sphere (else
  // its test costs more than it settles: with two spheres, testing both is as cheap), and
  // inside it, so the lanes' pose error bound covers its ends.
  std::vector<Eigen::Vector3d> centers;
  std::vector<double> radii;
  for (int i = b.begin; i < b.end; ++i) {
    centers.push_back(spheres_[std::size_t(i)].center);
    radii.push_back(spheres_[std::size_t(i)].radius);
  }
  const auto capsule = bounding_capsule(centers, radii);
  b.has_capsule = capsule && b.end - b.begin >= 3 && capsule->radius < 0.8 * b.radius &&
                  (capsule->from - b.center).norm() <= b.radius && (capsule->to - b.center).norm() <= b.radius;
  if (b.has_capsule) {
    b.capsule = *capsule;
    b.inv_len2 = 1.0 / (capsule->to - capsule->from).squaredNorm();
  }
}

// Reach from each chain joint above: the body's extent in its link frame plus every joint
// offset on the way up (a prismatic joint's offset grows by its largest travel).
void SphereFieldChecker::chain_body(Body& b, const std::vector<int>& parent_joint) {
  const auto& model = kin_->model();
  b.chain.clear();
  double reach = b.center.norm() + b.radius;
  link_reach_ = std::max(link_reach_, reach);
  for (int l = b.link, guard = 0; parent_joint[std::size_t(l)] >= 0 && guard <= int(model.joints.size()); ++guard) {
    const int j = parent_joint[std::size_t(l)];
    const Joint& jt = model.joints[std::size_t(j)];
    const bool prismatic = jt.type == JointType::Prismatic;
    if (kin_->chain_slot(j) >= 0)
      b.chain.push_back({kin_->chain_slot(j), prismatic ? 1.0 : reach, jt.child, jt.axis.normalized(), prismatic});
    reach += jt.origin.translation().norm() + (prismatic ? std::max(std::abs(jt.lower), std::abs(jt.upper)) : 0.0);
    l = jt.parent;
  }
  reach_ = std::max(reach_, reach);
}

void SphereFieldChecker::build_pair_spheres() {
  pair_spheres_.clear();
  for (auto& b : bodies_) {
    b.local = int(pair_spheres_.size());
    const int w = local_width(b);
    pair_spheres_.resize(pair_spheres_.size() + 4 * std::size_t(w), 0.0);
    double* at = pair_spheres_.data() + b.local;
    for (int k = 0; k < w; ++k) {
      const bool real = b.begin + k < b.end;
      const formats::LinkSphere& s = spheres_[std::size_t(real ? b.begin + k : b.begin)];
      // A spare lane: 1e6 m away on every axis, no radius, so no sphere reaches it.
      for (int d = 0; d < 3; ++d) at[d * w + k] = real ? s.center[d] : 1e6;
      at[3 * w + k] = real ? s.radius : 0.0;
    }
  }
}

// Joints above both bodies move them together: only the others change their distance.
SphereFieldChecker::PairMoves SphereFieldChecker::relative_moves(const Body& a, const Body& b) {
  auto only = [](const Body& x, const Body& y, std::vector<ChainJoint>& out, std::vector<int>& at) {
    for (std::size_t k = 0; k < x.chain.size(); ++k)
      if (std::none_of(y.chain.begin(), y.chain.end(),
                       [&](const ChainJoint& d) { return d.slot == x.chain[k].slot; })) {
        out.push_back(x.chain[k]);
        at.push_back(int(k));
      }
  };
  PairMoves m;
  only(a, b, m.a, m.a_at);
  only(b, a, m.b, m.b_at);
  return m;
}

// The body pairs checked for self-collision: moving ones not allowed to touch (the held object
// may touch the link holding it and the fingers), each with its self-distance table if any.
void SphereFieldChecker::build_pairs() {
  auto allowed = [&](int a, int b) {
    if (a == b) return true;
    for (auto [x, y] : allowed_)
      if ((x == a && y == b) || (x == b && y == a)) return true;
    return false;
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
        if (other == attached_link_ || std::find(touching_.begin(), touching_.end(), other) != touching_.end())
          continue;
        add_pair(i, j, -1);
        continue;
      }
      if (allowed(a.link, b.link)) continue;
      int table = -1;
      for (std::size_t t = 0; tables_ && t < tables_->size(); ++t) {
        const auto& tt = (*tables_)[t].data;
        if ((tt.link_a == a.link && tt.link_b == b.link) || (tt.link_a == b.link && tt.link_b == a.link))
          table = int(t);
      }
      add_pair(i, j, table);
    }
}

void SphereFieldChecker::build_static_reach() {
  static_reach_.setZero(Eigen::Index(bodies_.size() + pairs_.size()), Eigen::Index(kin_->dof()));
  auto add_reaches = [&](std::size_t row, const std::vector<ChainJoint>& joints) {
    for (const ChainJoint& j : joints) static_reach_(Eigen::Index(row), j.slot) += j.reach;
  };
  for (std::size_t bi = 0; bi < bodies_.size(); ++bi) add_reaches(bi, bodies_[bi].chain);
  for (std::size_t pi = 0; pi < pairs_.size(); ++pi) {
    add_reaches(bodies_.size() + pi, pair_moves_[pi].a);
    add_reaches(bodies_.size() + pi, pair_moves_[pi].b);
  }
}

void SphereFieldChecker::build_lane_bodies() {
  framed_version_ = kin_->lanes().version;
  for (const bool framed : {true, false}) {
    LaneBodies& out = framed ? framed_ : own_;
    out = {};
    out.spheres.resize(spheres_.size());
    for (const Body& b : bodies_) {
      const Eigen::Isometry3d T = framed ? kin_->lanes().frame_offset(b.link) : Eigen::Isometry3d::Identity();
      out.link.push_back(framed ? kin_->lanes().frame(b.link) : b.link);
      out.center.push_back(T * b.center);
      Capsule k = b.capsule;
      k.from = T * k.from, k.to = T * k.to;
      out.capsule.push_back(k);
      // The float poses' error bound must hold for points this far from their frame's origin.
      link_reach_ = std::max(link_reach_, out.center.back().norm() + b.radius);
      for (int i = b.begin; i < b.end; ++i) {
        const formats::LinkSphere& sp = spheres_[std::size_t(i)];
        const Eigen::Vector3d c = T * sp.center;
        LaneSphere& l = out.spheres[std::size_t(i)];
        std::fill_n(l.x, LinkPoseLanesD::kLanes, float(c.x()));
        std::fill_n(l.y, LinkPoseLanesD::kLanes, float(c.y()));
        std::fill_n(l.z, LinkPoseLanesD::kLanes, float(c.z()));
        std::fill_n(l.r, LinkPoseLanesD::kLanes, float(sp.radius));
      }
    }
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
    throw Error("SphereFieldChecker", "attached object", "centers and radii differ in count");
  SphereFieldChecker c = *this;
  if (c.attached_link_ >= 0) c.spheres_.resize(std::size_t(c.attached_begin_));  // replace a previous object
  c.attached_link_ = object.link;
  c.attached_begin_ = int(c.spheres_.size());
  c.touching_ = std::move(object.touching_links);
  for (std::size_t i = 0; i < object.centers.size(); ++i)
    c.spheres_.push_back({object.link, object.centers[i], object.radii[i]});
  c.build_bodies();
  return c;
}

SphereFieldChecker SphereFieldChecker::with_kinematics(const Kinematics& kin) const {
  if (&kin.model() != &kin_->model())
    throw Error("SphereFieldChecker", "kinematics",
                "a different robot model: only joint values outside the chain may differ");
  SphereFieldChecker c = *this;
  c.kin_ = &kin;
  c.build_bodies();  // reaches come from the model (prismatic travel included), rebuilt anyway
  return c;
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

SphereCheck SphereFieldChecker::check_along(const Eigen::VectorXd& q, const Eigen::VectorXd& direction,
                                            double enough) const {
  return evaluate(q, poses_at(q), &direction, enough);
}

SphereCheck SphereFieldChecker::check_along(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses,
                                            const Eigen::VectorXd& direction, double enough) const {
  return evaluate(q, poses, &direction, enough);
}

SphereFieldChecker::Pass::Scratch& SphereFieldChecker::Pass::thread_scratch() {
  thread_local Scratch scratch;
  return scratch;
}

SphereFieldChecker::Pass::Pass(const SphereFieldChecker& checker, const Eigen::VectorXd* q_,
                               const std::vector<Eigen::Isometry3d>& poses_, const Eigen::VectorXd* dir_,
                               double enough_)
    : c(checker), q(q_), poses(poses_), dir(dir_), enough(enough_),
      certify(dir_ && checker.certifiable_ && enough_ > 0),  // enough 0: the caller needs no certificate
      s(thread_scratch()) {
  const std::size_t nb = c.bodies_.size(), ns = c.spheres_.size();
  s.body_center.resize(nb);
  s.world.resize(ns);
  s.body_flags.assign(nb, 0);
  if (c.exact_scene()) s.sphere_exact.resize(ns);
  s.cands.clear();
  s.times.clear();
  if (certify) {
    s.body_clear.assign(nb, std::numeric_limits<double>::infinity());
    s.sphere_coarse.resize(ns);
    s.sphere_fine.resize(ns);
    s.sphere_exact.resize(ns);
    s.sphere_gap.resize(ns);
    s.slot_done.assign(std::size_t(dir->size()), 0);
    s.lever.resize(std::size_t(c.lever_count_));
    s.lever_norm.resize(std::size_t(c.lever_count_));
    s.slot_axis.resize(std::size_t(dir->size()));
    s.slot_origin.resize(std::size_t(dir->size()));
  }
  out.min_clearance = c.band_;
}

SphereCheck SphereFieldChecker::evaluate(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses,
                                         const Eigen::VectorXd* dir, double enough) const {
  if (poses.size() != kin_->model().links.size())
    throw Error("SphereFieldChecker", "link poses", "one pose per link expected");
  Pass pass(*this, &q, poses, dir, enough);
  if (pass.environment() && pass.self_pairs() && pass.certify) pass.certificate();
  return pass.out;
}

double SphereFieldChecker::link_time(const std::vector<Eigen::Isometry3d>& poses, int link, double gap,
                                     const Eigen::VectorXd& direction) const {
  DisplacementBound v;
  return gap > 0 && link_speed(poses, link, direction, v) ? v.time_to_move(gap) : 0.0;
}

double SphereFieldChecker::pair_time(const std::vector<Eigen::Isometry3d>& poses, int link_a, int link_b, double gap,
                                     const Eigen::VectorXd& direction) const {
  DisplacementBound v;
  return gap > 0 && pair_speed(poses, link_a, link_b, direction, v) ? v.time_to_move(gap) : 0.0;
}

bool SphereFieldChecker::link_speed(const std::vector<Eigen::Isometry3d>& poses, int link,
                                    const Eigen::VectorXd& direction, DisplacementBound& bound,
                                    BallVelocity* velocity) const {
  if (!certifiable_) return false;
  for (std::size_t bi = 0; bi < bodies_.size(); ++bi) {
    const Body& b = bodies_[bi];
    if (b.link != link || b.attached) continue;
    Pass pass(*this, nullptr, poses, &direction, std::numeric_limits<double>::infinity());
    pass.s.body_center[bi] = poses[std::size_t(link)] * b.center;
    bound = pass.body_speed(bi, velocity);
    return true;
  }
  return false;
}

bool SphereFieldChecker::pair_speed(const std::vector<Eigen::Isometry3d>& poses, int link_a, int link_b,
                                    const Eigen::VectorXd& direction, DisplacementBound& bound) const {
  if (!certifiable_) return false;
  for (std::size_t pi = 0; pi < pairs_.size(); ++pi) {
    const auto ia = std::size_t(pairs_[pi].a), ib = std::size_t(pairs_[pi].b);
    const Body &a = bodies_[ia], &b = bodies_[ib];
    if (a.attached || b.attached || !((a.link == link_a && b.link == link_b) || (a.link == link_b && b.link == link_a)))
      continue;
    Pass pass(*this, nullptr, poses, &direction, std::numeric_limits<double>::infinity());
    pass.s.body_center[ia] = poses[std::size_t(a.link)] * a.center;
    pass.s.body_center[ib] = poses[std::size_t(b.link)] * b.center;
    bound = pass.pair_speed(pi);
    return true;
  }
  return false;
}

}  // namespace dmgplace::runtime
