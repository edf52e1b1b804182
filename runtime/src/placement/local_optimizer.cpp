#include "dmgplace/runtime/placement/local_optimizer.hpp"

#include <cmath>

namespace dmgplace::runtime {

LocalOptimum optimize_locally(const LocalProblem& p, const Eigen::VectorXd& q_start, const Eigen::Isometry3d& resting,
                              const PlacementOptions& o) {
  LocalOptimum out;
  out.pose = resting;
  out.objective = out.start_objective = p.objective->value(resting);
  if (!o.optimize_locally) return out;
  IkOptions ik_opt;
  ik_opt.max_restarts = 0;  // continuation from the current configuration only
  ik_opt.max_iterations = 30;
  const IkSolver ik(*p.kin, ik_opt);
  std::mt19937_64 unused_rng(0);
  auto valid = [&](const Eigen::VectorXd& q) { return p.checker->is_free(q); };
  Eigen::VectorXd q = q_start;
  double step = o.local_step;
  // A joint jump this large means IK left the branch the path is on.
  const double max_jump = std::max(0.2, 4 * o.motion_resolution);
  for (int it = 0; it < o.local_iterations && step >= o.local_min_step; ++it) {
    ++out.iterations;
    const Eigen::Vector3d g = p.objective->gradient(out.pose);
    if (!(g.norm() > 1e-9)) break;  // flat (or NaN): nothing to follow
    const Eigen::Isometry3d cand = p.objective->moved(out.pose, g.normalized() * step);
    const double value = p.objective->value(cand);
    Eigen::Isometry3d up = cand;
    up.translation().z() += p.lift;
    bool ok = value > out.objective && p.space->stable(p.face, p.region, cand);
    IkResult r;
    if (ok) {
      r = ik.solve(up * p.tcp_in_object, q, unused_rng);
      ok =
          r.success && (r.q - q).cwiseAbs().maxCoeff() <= max_jump && segment_valid(q, r.q, o.motion_resolution, valid);
    }
    if (!ok) {
      step *= 0.5;
      continue;
    }
    q = r.q;
    out.steps.push_back(std::vector<double>(q.data(), q.data() + q.size()));
    out.pose = cand;
    out.objective = value;
    out.poses.push_back(cand);
    out.values.push_back(value);
  }
  return out;
}

}  // namespace dmgplace::runtime
