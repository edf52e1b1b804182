#include "dmgplace/tools/robot/allowed_collisions.hpp"

#include <algorithm>
#include <map>
#include <numbers>
#include <random>
#include <sstream>

#include "../system/parallel_for.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::tools {

const char* to_string(DisableReason r) {
  switch (r) {
    case DisableReason::Adjacent:
      return "Adjacent";
    case DisableReason::Default:
      return "Default";
    case DisableReason::Always:
      return "Always";
    case DisableReason::Never:
      return "Never";
  }
  return "?";
}

int AllowedCollisions::count(DisableReason r) const {
  return int(std::count_if(disabled.begin(), disabled.end(), [r](const DisabledPair& p) { return p.reason == r; }));
}

AllowedCollisions compute_allowed_collisions(const RobotModel& input, const AllowedCollisionOptions& o) {
  RobotModel model = input;
  model.allowed_pairs.clear();  // decide every pair afresh
  const std::size_t nl = model.links.size();
  auto has_geometry = [&](int l) { return !model.links[std::size_t(l)].collision.empty(); };
  std::vector<int> parent_link(nl, -1);
  for (const auto& j : model.joints) parent_link[std::size_t(j.child)] = j.parent;

  std::map<std::pair<int, int>, DisableReason> decided;
  // Adjacent: each link with geometry and its nearest ancestor with geometry.
  for (int l = 0; l < int(nl); ++l) {
    if (!has_geometry(l)) continue;
    int p = parent_link[std::size_t(l)];
    for (std::size_t guard = 0; p >= 0 && !has_geometry(p) && guard < nl; ++guard) p = parent_link[std::size_t(p)];
    if (p >= 0) decided.emplace(std::minmax(l, p), DisableReason::Adjacent);
  }

  const runtime::Kinematics kin(model, model.arm_base, model.arm_tip);
  const runtime::ExactChecker checker(kin, Scene{});
  std::vector<Eigen::Isometry3d> poses;
  // Default pose: every chain joint at 0, clamped to its limits.
  kin.link_poses(Eigen::VectorXd::Zero(kin.dof()).cwiseMax(kin.lower()).cwiseMin(kin.upper()), poses);
  for (const auto& pair : checker.colliding_link_pairs(poses)) decided.emplace(pair, DisableReason::Default);

  // Random configurations of every joint that moves, the chain's and the others' (another arm may
  // plan later, as a pusher), as MoveIt's setup assistant samples them: how often each pair collides.
  std::vector<int> others;
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& jt = model.joints[j];
    if (jt.type != JointType::Fixed && jt.mimic < 0 && kin.chain_slot(int(j)) < 0) others.push_back(int(j));
  }
  // The configurations drawn in order, then checked in parallel (each thread its own kinematics).
  std::mt19937_64 rng(o.seed);
  const int samples = std::max(1, o.samples);
  std::vector<Eigen::VectorXd> chain(static_cast<std::size_t>(samples), Eigen::VectorXd(kin.dof()));
  std::vector<std::vector<double>> rest(static_cast<std::size_t>(samples));
  for (int s = 0; s < samples; ++s) {
    for (int i = 0; i < kin.dof(); ++i)
      chain[std::size_t(s)][i] = std::uniform_real_distribution<double>(kin.lower()[i], kin.upper()[i])(rng);
    for (int j : others) {
      const Joint& jt = model.joints[std::size_t(j)];
      const bool turns = jt.type == JointType::Continuous;
      rest[std::size_t(s)].push_back(std::uniform_real_distribution<double>(turns ? -std::numbers::pi : jt.lower,
                                                                            turns ? std::numbers::pi : jt.upper)(rng));
    }
  }
  std::vector<std::vector<std::pair<int, int>>> colliding(static_cast<std::size_t>(samples));
  const std::size_t parts = std::size_t(std::max(1, o.threads > 0 ? o.threads : runtime::available_cpus())),
                    n = chain.size();
  detail::parallel_for(parts, int(parts), [&](std::size_t part) {
    runtime::Kinematics sampled(kin);  // other joints set per sample: one copy per part
    std::vector<Eigen::Isometry3d> at;
    for (std::size_t s = part * n / parts; s < (part + 1) * n / parts; ++s) {
      for (std::size_t k = 0; k < others.size(); ++k)
        sampled.set_joint_value(model.joints[std::size_t(others[k])].name, rest[s][k]);
      sampled.link_poses(chain[s], at);
      colliding[s] = checker.colliding_link_pairs(at);
    }
  });
  std::map<std::pair<int, int>, int> hits;
  for (const auto& pairs : colliding)
    for (const auto& pair : pairs) ++hits[pair];
  AllowedCollisions out;
  out.samples = samples;
  for (int a = 0; a < int(nl); ++a)
    for (int b = a + 1; b < int(nl); ++b) {
      if (!has_geometry(a) || !has_geometry(b)) continue;
      ++out.checked_pairs;
      const std::pair<int, int> pair{a, b};
      if (auto it = decided.find(pair); it != decided.end()) {
        out.disabled.push_back({a, b, it->second});
        continue;
      }
      const int h = hits.count(pair) ? hits[pair] : 0;
      if (h == samples) out.disabled.push_back({a, b, DisableReason::Always});
      else if (h == 0) out.disabled.push_back({a, b, DisableReason::Never});
      else out.checked.push_back({a, b, h});
    }
  return out;
}

std::string srdf_text(const RobotModel& model, const std::vector<DisabledPair>& pairs) {
  std::ostringstream s;
  s << "<?xml version=\"1.0\"?>\n"
    << "<!-- Written by dmgplace bake-robot: the link pairs it allowed to touch. Review, then pass back with --srdf. "
       "-->\n"
    << "<robot name=\"" << model.name << "\">\n";
  for (const auto& p : pairs)
    s << "  <disable_collisions link1=\"" << model.links[std::size_t(p.a)].name << "\" link2=\""
      << model.links[std::size_t(p.b)].name << "\" reason=\"" << to_string(p.reason) << "\"/>\n";
  s << "</robot>\n";
  return s.str();
}

}  // namespace dmgplace::tools
