#include "dmgplace/runtime/robot/ik.hpp"

#include <cmath>

namespace dmgplace::runtime {
namespace {
// x with A x = b, A symmetric positive definite (the damped normal matrix): Cholesky with loops of
// fixed bounds the compiler unrolls (Eigen's LLT runs its loops at run time at this size).
Eigen::Matrix<double, 6, 1> solve_spd6(const Eigen::Matrix<double, 6, 6>& A, const Eigen::Matrix<double, 6, 1>& b) {
  double L[6][6], inv[6];
  for (int j = 0; j < 6; ++j) {
    double d = A(j, j);
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    inv[j] = 1.0 / std::sqrt(d);
    for (int i = j + 1; i < 6; ++i) {
      double v = A(i, j);
      for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
      L[i][j] = v * inv[j];
    }
  }
  double y[6];
  for (int i = 0; i < 6; ++i) {
    double v = b[i];
    for (int k = 0; k < i; ++k) v -= L[i][k] * y[k];
    y[i] = v * inv[i];
  }
  Eigen::Matrix<double, 6, 1> x;
  for (int i = 5; i >= 0; --i) {
    double v = y[i];
    for (int k = i + 1; k < 6; ++k) v -= L[k][i] * x[k];
    x[i] = v * inv[i];
  }
  return x;
}
}  // namespace

Eigen::Matrix<double, 6, 1> pose_error(const Eigen::Isometry3d& cur, const Eigen::Isometry3d& target) {
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = target.translation() - cur.translation();
  Eigen::AngleAxisd aa(target.linear() * cur.linear().transpose());
  e.tail<3>() = aa.axis() * aa.angle();
  return e;
}

bool IkSolver::descend(const Eigen::Isometry3d& target, Eigen::VectorXd& q, IkResult& r) const {
  const int n = kin_.dof();
  // Sized once per descent: the loop below does not allocate.
  Jacobian J(6, n), J_new(6, n), Jw(6, n);
  Eigen::Matrix<double, 6, 1> w;
  w << 1, 1, 1, opt_.orientation_weight, opt_.orientation_weight, opt_.orientation_weight;
  auto weighted_error = [&](const Eigen::VectorXd& qq, Jacobian* jac) {
    Eigen::Isometry3d t = jac ? kin_.tip_pose_and_jacobian(qq, *jac) : kin_.tip_pose(qq);
    return Eigen::Matrix<double, 6, 1>(pose_error(t, target).cwiseProduct(w));
  };
  Eigen::Matrix<double, 6, 1> e = weighted_error(q, &J);
  double cost = e.squaredNorm();
  double lambda = 1e-3;
  Eigen::VectorXd q_new(n);
  for (int it = 0; it < opt_.max_iterations; ++it) {
    ++r.iterations;
    const double pos = e.head<3>().norm(), rot = e.tail<3>().norm() / opt_.orientation_weight;
    r.position_error = pos;
    r.orientation_error = rot;
    if (pos < opt_.position_tolerance && rot < opt_.orientation_tolerance) return true;
    Jw.noalias() = w.asDiagonal() * J;
    Eigen::Matrix<double, 6, 6> A;
    A.noalias() = Jw * Jw.transpose();
    A.diagonal().array() += lambda * (1.0 + A.diagonal().array());
    // Positive definite (damping on the diagonal): Cholesky without pivoting.
    const Eigen::Matrix<double, 6, 1> step = solve_spd6(A, e);
    q_new.noalias() = q + Jw.transpose() * step;
    q_new = q_new.cwiseMax(kin_.lower()).cwiseMin(kin_.upper());
    Eigen::Matrix<double, 6, 1> e_new = weighted_error(q_new, &J_new);
    const double cost_new = e_new.squaredNorm();
    if (cost_new < cost) {
      q = q_new;
      e = e_new;
      J.swap(J_new);
      cost = cost_new;
      lambda = std::max(lambda * 0.3, 1e-7);
    } else {
      lambda *= 10;
      if (lambda > 1e6) break;  // stuck at a limit or a local minimum: restart
    }
  }
  r.position_error = e.head<3>().norm();
  r.orientation_error = e.tail<3>().norm() / opt_.orientation_weight;
  return r.position_error < opt_.position_tolerance && r.orientation_error < opt_.orientation_tolerance;
}

IkResult IkSolver::solve(const Eigen::Isometry3d& target, const Eigen::VectorXd& seed, std::mt19937_64& rng) const {
  IkResult r;
  if (!target.matrix().allFinite()) {
    r.reason = "invalid target (not finite)";
    return r;
  }
  const int n = kin_.dof();
  Eigen::VectorXd q(n);
  if (seed.size() == n && seed.allFinite()) q = seed.cwiseMax(kin_.lower()).cwiseMin(kin_.upper());
  else q = 0.5 * (kin_.lower() + kin_.upper());
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double best = std::numeric_limits<double>::infinity();
  for (int start = 0; start <= opt_.max_restarts; ++start) {
    if (start > 0)
      for (int i = 0; i < n; ++i) q[i] = kin_.lower()[i] + u(rng) * (kin_.upper()[i] - kin_.lower()[i]);
    ++r.starts;
    IkResult attempt;
    const bool ok = descend(target, q, attempt);
    r.iterations += attempt.iterations;
    const double score = attempt.position_error + attempt.orientation_error * opt_.orientation_weight;
    if (ok) {
      r.success = true;
      r.q = q;
      r.position_error = attempt.position_error;
      r.orientation_error = attempt.orientation_error;
      r.reason.clear();
      return r;
    }
    if (score < best) {
      best = score;
      r.q = q;
      r.position_error = attempt.position_error;
      r.orientation_error = attempt.orientation_error;
    }
  }
  // Distinguish "pressed against a limit" from plain non-convergence for the caller.
  bool at_limit = false;
  for (int i = 0; i < n; ++i)
    at_limit |= std::abs(r.q[i] - kin_.lower()[i]) < 1e-9 || std::abs(r.q[i] - kin_.upper()[i]) < 1e-9;
  r.reason = at_limit ? "not converged (best attempt pressed against joint limits)" : "not converged";
  return r;
}

}  // namespace dmgplace::runtime
