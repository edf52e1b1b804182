#include "dmgplace/runtime/collision/sphere_field_checker.hpp"

#include <algorithm>
#include <cmath>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::runtime {
SphereFieldChecker::SphereFieldChecker(const Kinematics& kin, std::vector<formats::LinkSphere> spheres,
                                       std::shared_ptr<const Grid3> sdf, double band, double padding)
    : kin_(&kin), spheres_(std::move(spheres)), allowed_(kin.model().allowed_pairs), sdf_(std::move(sdf)),
      band_(band), padding_(padding) {
  if (!sdf_) throw Error("SphereFieldChecker", "", "no distance field");
  // Trilinear interpolation of a 1-Lipschitz distance can overestimate it by at most the mean
  // distance to the cell corners, <= sqrt(3)/2 * resolution (at the cell centre).
  margin_ = std::sqrt(3.0) / 2.0 * sdf_->resolution();
  lo_ = sdf_->origin();
  hi_ = sdf_->point(sdf_->dims()[0] - 1, sdf_->dims()[1] - 1, sdf_->dims()[2] - 1);
  for (const auto& s : spheres_)
    if (s.link < 0 || std::size_t(s.link) >= kin.model().links.size())
      throw Error("SphereFieldChecker", "spheres", "link index out of range");
  std::stable_sort(spheres_.begin(), spheres_.end(),
                   [](const formats::LinkSphere& a, const formats::LinkSphere& b) { return a.link < b.link; });
  build_bodies();
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
  for (auto& b : bodies_) {
    b.moving = moving[std::size_t(b.link)];
    // Bounding sphere: centre of the spheres' box, radius reaching every sphere's far side.
    Eigen::AlignedBox3d box;
    for (int i = b.begin; i < b.end; ++i) box.extend(spheres_[std::size_t(i)].center);
    b.center = box.center();
    for (int i = b.begin; i < b.end; ++i)
      b.radius = std::max(b.radius, (spheres_[std::size_t(i)].center - b.center).norm() + spheres_[std::size_t(i)].radius);
  }
  auto allowed = [&](int a, int b) {
    if (a == b) return true;
    for (auto [x, y] : allowed_)
      if ((x == a && y == b) || (x == b && y == a)) return true;
    return false;
  };
  pairs_.clear();
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    for (std::size_t j = i + 1; j < bodies_.size(); ++j) {
      const Body &a = bodies_[i], &b = bodies_[j];
      if (!a.moving && !b.moving && !a.attached && !b.attached) continue;  // never changes: not our concern
      if (a.attached || b.attached) {
        const int other = a.attached ? b.link : a.link;
        // The object may touch the link holding it and the fingers.
        if (other == attached_link_ || std::find(touching_.begin(), touching_.end(), other) != touching_.end()) continue;
        pairs_.push_back({int(i), int(j)});
        continue;
      }
      if (!allowed(a.link, b.link)) pairs_.push_back({int(i), int(j)});
    }
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

SphereCheck SphereFieldChecker::check(const Eigen::VectorXd& q) const {
  thread_local std::vector<Eigen::Isometry3d> poses;
  thread_local std::vector<Eigen::Vector3d> body_center, world;
  thread_local std::vector<char> world_done;
  kin_->link_poses(q, poses);
  body_center.resize(bodies_.size());
  world.resize(spheres_.size());
  world_done.assign(bodies_.size(), 0);
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
  const double pad = margin_ + padding_;
  auto outside = [&](const Eigen::Vector3d& p) { return ((p - lo_).array() < 0).any() || ((hi_ - p).array() < 0).any(); };
  for (std::size_t bi = 0; bi < bodies_.size(); ++bi) {
    const Body& b = bodies_[bi];
    const Eigen::Isometry3d& T = poses[std::size_t(b.link)];
    body_center[bi] = T * b.center;
    if (!b.moving && !b.attached) continue;
    if (!outside(body_center[bi])) {
      const double d = sdf_->sample(body_center[bi]) - b.radius - pad;
      if (d >= 0) {
        out.min_clearance = std::min(out.min_clearance, d);
        continue;  // the whole body is clear
      }
    }
    centres(bi);
    // Keep going after a hit: every flagged link is listed, so the exact layer can check just those.
    for (int i = b.begin; i < b.end; ++i) {
      const auto& s = spheres_[std::size_t(i)];
      const Eigen::Vector3d& w = world[std::size_t(i)];
      // Outside the grid nothing is known: "maybe in collision", for the exact layer to decide.
      // (Band-clamped far cells are fine: clamping only lowers values, which stays conservative.)
      const bool out_of_grid = outside(w);
      const double clearance = out_of_grid ? -1.0 : sdf_->sample(w) - s.radius - pad;
      if (!out_of_grid) out.min_clearance = std::min(out.min_clearance, clearance);
      if (clearance < 0) {
        out.environment_free = false;
        out.outside_grid |= out_of_grid;
        if (b.attached) out.attached_near_env = true;
        else if (out.env_link_count < SphereCheck::kMaxPairs) out.env_links[std::size_t(out.env_link_count++)] = b.link;
        else out.env_overflow = true;
        break;
      }
    }
  }
  for (const auto& p : pairs_) {
    const Body &a = bodies_[std::size_t(p.a)], &b = bodies_[std::size_t(p.b)];
    const double rb = a.radius + b.radius + padding_;
    if ((body_center[std::size_t(p.a)] - body_center[std::size_t(p.b)]).squaredNorm() >= rb * rb) continue;
    centres(std::size_t(p.a));
    centres(std::size_t(p.b));
    bool hit = false;
    for (int i = a.begin; i < a.end && !hit; ++i) {
      const Eigen::Vector3d& wa = world[std::size_t(i)];
      for (int j = b.begin; j < b.end; ++j) {
        const double r = spheres_[std::size_t(i)].radius + spheres_[std::size_t(j)].radius + padding_;
        if ((wa - world[std::size_t(j)]).squaredNorm() < r * r) {
          hit = true;
          break;
        }
      }
    }
    if (!hit) continue;
    out.self_free = false;
    if (a.attached || b.attached) out.attached_involved = true;
    if (out.pair_count == SphereCheck::kMaxPairs) {
      out.pairs_overflow = true;
      return out;
    }
    out.pairs[std::size_t(out.pair_count++)] = {a.link, b.link};
  }
  return out;
}

}  // namespace dmgplace::runtime
