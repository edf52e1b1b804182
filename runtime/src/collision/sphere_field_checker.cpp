#include "dmgplace/runtime/collision/sphere_field_checker.hpp"

#include <algorithm>
#include <cmath>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::runtime {
namespace {
// Links whose pose depends on the chain's joints (descendants of its first moving joint).
std::vector<char> moving_links(const Kinematics& kin) {
  const auto& m = kin.model();
  std::vector<char> moving(m.links.size(), 0);
  Eigen::VectorXd q0 = 0.5 * (kin.lower() + kin.upper());
  std::vector<Eigen::Isometry3d> a, b;
  kin.link_poses(q0, a);
  // Perturb every joint: a link that moves under any perturbation is moving.
  for (int i = 0; i < kin.dof(); ++i) {
    Eigen::VectorXd q = q0;
    q[i] += 0.1;
    kin.link_poses(q, b);
    for (std::size_t l = 0; l < a.size(); ++l) moving[l] |= !a[l].isApprox(b[l], 1e-12);
  }
  return moving;
}
}  // namespace

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
  build_pairs();
}

void SphereFieldChecker::build_pairs() {
  const auto moving = moving_links(*kin_);
  check_env_.assign(spheres_.size(), 0);
  for (std::size_t i = 0; i < spheres_.size(); ++i) check_env_[i] = moving[std::size_t(spheres_[i].link)];
  auto allowed = [&](int a, int b) {
    if (a == b) return true;
    for (auto [x, y] : allowed_)
      if ((x == a && y == b) || (x == b && y == a)) return true;
    return false;
  };
  pairs_.clear();
  for (std::size_t i = 0; i < spheres_.size(); ++i)
    for (std::size_t j = i + 1; j < spheres_.size(); ++j) {
      int a = spheres_[i].link, b = spheres_[j].link;
      if (!moving[std::size_t(a)] && !moving[std::size_t(b)]) continue;  // never changes: not our concern
      if (!allowed(a, b)) pairs_.push_back({int(i), int(j)});
    }
}

SphereFieldChecker SphereFieldChecker::with_attached(AttachedSpheres object) const {
  SphereFieldChecker c = *this;
  c.attached_link_ = object.link;
  if (object.link < 0 || std::size_t(object.link) >= kin_->model().links.size())
    throw Error("SphereFieldChecker", "attached object", "link index out of range");
  // The attached body is modelled as a pseudo-link index: it shares the tip link's frame but gets
  // its own allowed pairs (the fingers and the link it hangs from).
  for (std::size_t i = 0; i < object.centers.size(); ++i) c.spheres_.push_back({object.link, object.centers[i], object.radii[i]});
  c.build_pairs();
  // Remove pairs between the object's spheres and the links it may touch (and its own link).
  const std::size_t first = spheres_.size();
  std::vector<Pair> kept;
  for (const auto& p : c.pairs_) {
    const bool a_obj = std::size_t(p.a) >= first, b_obj = std::size_t(p.b) >= first;
    if (a_obj || b_obj) {
      const int other = c.spheres_[std::size_t(a_obj ? p.b : p.a)].link;
      if (std::find(object.touching_links.begin(), object.touching_links.end(), other) != object.touching_links.end())
        continue;
    }
    kept.push_back(p);
  }
  // Pairs between the object and its own link are dropped by build_pairs (same link index), which
  // is right: it is held by that link.
  c.pairs_ = std::move(kept);
  return c;
}

SphereCheck SphereFieldChecker::check(const Eigen::VectorXd& q) const {
  thread_local std::vector<Eigen::Isometry3d> poses;
  thread_local std::vector<Eigen::Vector3d> world;
  kin_->link_poses(q, poses);
  world.resize(spheres_.size());
  SphereCheck out;
  out.min_clearance = band_;
  for (std::size_t i = 0; i < spheres_.size(); ++i) {
    const auto& s = spheres_[i];
    world[i] = poses[std::size_t(s.link)] * s.center;
    if (!check_env_[i]) continue;
    // Outside the grid nothing is known: "maybe in collision", for the exact layer to decide.
    // (Band-clamped far cells are fine: clamping only lowers values, which stays conservative.)
    if (((world[i] - lo_).array() < 0).any() || ((hi_ - world[i]).array() < 0).any()) {
      out.environment_free = false;
      out.outside_grid = true;
      return out;
    }
    const double d = sdf_->sample(world[i]);
    const double clearance = d - s.radius - margin_ - padding_;
    out.min_clearance = std::min(out.min_clearance, clearance);
    if (clearance < 0) {
      out.environment_free = false;
      return out;
    }
  }
  for (const auto& p : pairs_) {
    const double r = spheres_[std::size_t(p.a)].radius + spheres_[std::size_t(p.b)].radius + padding_;
    if ((world[std::size_t(p.a)] - world[std::size_t(p.b)]).squaredNorm() >= r * r) continue;
    out.self_free = false;
    const std::pair<int, int> links{spheres_[std::size_t(p.a)].link, spheres_[std::size_t(p.b)].link};
    bool known = false;
    for (int i = 0; i < out.pair_count; ++i) known |= out.pairs[std::size_t(i)] == links;
    if (known) continue;
    if (out.pair_count == SphereCheck::kMaxPairs) {
      out.pairs_overflow = true;
      return out;
    }
    out.pairs[std::size_t(out.pair_count++)] = links;
  }
  return out;
}

}  // namespace dmgplace::runtime
