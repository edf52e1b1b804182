#include "dmgplace/runtime/motion/certified_motion_validator.hpp"

#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <cmath>

namespace ob = ompl::base;

namespace dmgplace::runtime {
namespace {
constexpr int kBatch = 8;  // SphereFieldChecker::free_lanes' lanes
constexpr int kBatchRange = 2 * kBatch;  // wider uncertified ranges are bisected (fewer states, when certificates return)
// A span batch's lanes reach T states each way, where T x kSpanShare is within the neighbouring
// certificate: the batch widens by a static speed bound, which lasts about half as far as a
// certificate's local one (bench-mbm: shares 1.5-2 best, smaller ones slower; docs/perf-log.md).
constexpr int kSpanShare = 2;
// Far ends go into the first batch's last lane while fewer than this share of recent ones were
// blocked (CertifiedMotionValidator::far_blocked_). A blocked one then costs a batch more than a
// plain check first; a free one the batch proves costs nothing more. On the planners' median
// problems, where far ends are often blocked, this share was level with or faster than never
// using the lane, and faster than a higher share or always; open-space motions, seldom blocked,
// gain most (docs/perf-log.md).
constexpr double kFarLaneBlockedShare = 0.1;
Eigen::Map<const Eigen::VectorXd> values(const ob::State* s, unsigned n) {
  return {s->as<ob::RealVectorStateSpace::StateType>()->values, Eigen::Index(n)};
}

// The straight motion s1 -> s2 as the discrete validator sees it: `steps` states h apart. Its
// vectors are this thread's buffers, sized once (a motion check allocated three vectors, and one
// more per state checked, which cost measurable time): one segment per thread at a time, which
// holds as a validator's checks do not nest.
struct Segment {
  Eigen::VectorXd &a, &dir;
  double length = 0, h = 0;
  int steps = 1;
  Segment(const ob::SpaceInformation& si, const ob::State* s1, const ob::State* s2) : a(buffer(0)), dir(buffer(1)) {
    const unsigned n = si.getStateDimension();
    a = values(s1, n);
    dir = values(s2, n) - a;
    length = dir.norm();
    steps = std::max(1, int(std::ceil(length / si.getStateSpace()->getLongestValidSegmentLength())));
    if (length > 0) dir /= length;
    else dir.setZero();
    h = length / steps;
  }
  // State i, in a third buffer: valid until the next call.
  const Eigen::VectorXd& at(int i) const {
    Eigen::VectorXd& q = buffer(2);
    q.noalias() = a + (i * h) * dir;
    return q;
  }
  static Eigen::VectorXd& buffer(int k) {
    thread_local Eigen::VectorXd v[3];
    return v[k];
  }
};
}  // namespace

CertifiedMotionValidator::CertifiedMotionValidator(const ob::SpaceInformationPtr& si, CertificateFn certificate,
                                                   ProvenFreeFn proven_free)
    : ob::MotionValidator(si), certificate_(std::move(certificate)), proven_free_(std::move(proven_free)) {}

CertifiedMotionValidator::CertifiedMotionValidator(const ob::SpaceInformationPtr& si, FreeDistanceFn free_distance,
                                                   ProvenFreeFn proven_free)
    : CertifiedMotionValidator(si, certificate_of(std::move(free_distance)), std::move(proven_free)) {}

CertifiedMotionValidator::CertificateFn CertifiedMotionValidator::certificate_of(FreeDistanceFn free_distance) {
  if (!free_distance) return nullptr;
  return [fd = std::move(free_distance)](const Eigen::VectorXd& q, const Eigen::VectorXd& dir, double enough) {
    const double t = fd(q, dir, enough);
    return Certificate{t, t};
  };
}

bool CertifiedMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2) const {
  return check_motion(s1, s2, false);
}

bool CertifiedMotionValidator::checkMotionBetweenValid(const ob::State* s1, const ob::State* s2) const {
  return check_motion(s1, s2, true);
}

bool CertifiedMotionValidator::check_motion(const ob::State* s1, const ob::State* s2, bool end_valid) const {
  const Segment seg(*si_, s1, s2);
  const int steps = seg.steps;
  // A certificate is symmetric (speeds bound |direction|): state i proves states i-k .. i+k.
  // `need` steps on either side is all that is left to prove around i.
  // k: the states the certificate covers each way; `span_k` (optional): its isotropic estimate's.
  auto check = [&](int i, int need, int& k, int* span_k = nullptr) {
    // Nothing left to prove around i (a bisection leaf): a plain check, no certificate work.
    const Certificate c = certificate_(seg.at(i), seg.dir, need > 0 ? (need + 1e-6) * seg.h : 0.0);
    if (c.reach < 0) return false;
    auto states = [&](double t) { return seg.h > 0 ? int(std::min(t / seg.h, double(steps))) : steps; };
    k = states(c.reach);
    if (span_k) *span_k = std::min(k, states(c.estimate));
    return true;
  };
  // With batch proofs a certificate need only reach a batch's width: what lies beyond goes to span
  // batches, which take it as their estimate. Refining further had made bisection midpoints the
  // costliest checks (bench-mbm over needs from 1 state to the whole range: 8 best).
  auto need_of = [&](int states) { return proven_free_ ? std::min(states, kBatch) : states; };
  int k = 0, span_k = 0;
  // The far end first: a bad goal is found at once. With batch proofs a plain check, and span
  // batches take the whole motion from there: a certificate at the far end (8 states) cost more
  // than the lanes it spared (docs/motion.md, "Certified motion validation"). Where far ends are
  // seldom blocked, not even that: the first batch's last lane
  // takes the far end, and only a far end it leaves unproven gets a plain check, before anything
  // else (far_in_batch).
  bool far_in_batch = false;
  if (!end_valid && proven_free_ && steps > 1 &&
      far_blocked_.load(std::memory_order_relaxed) < std::uint32_t(kFarLaneBlockedShare * 65536.0)) {
    far_in_batch = true;
    span_k = steps;
  } else if (!end_valid) {
    if (!check(steps, proven_free_ ? 0 : steps - 1, k, &span_k)) {
      far_end_was(true);
      ++invalid_;
      return false;
    }
    far_end_was(false);
    if (proven_free_) k = 0, span_k = steps;
  }
  // Unchecked index ranges [lo, hi] (state 0 is valid by contract), bisected breadth first as
  // OMPL's discrete validator does, minus what each checked state certifies around itself. Each
  // range keeps the certificate of the check that made it, an estimate e of the next one's: a range
  // a little wider than one certificate (2e + 1 < size <= 4e + 2) is tiled from its left end
  // (two checks) rather than split in the middle (which leaves a one-state range on each side).
  // The span estimate is the same certificate's under isotropic bounds (Certificate::estimate).
  struct Range {
    int lo, hi, estimate, span_estimate;
    bool certified_only = false;  // a span batch's lane left it: certified checks from here on
  };
  // A range the last certificate did not reach beyond its own state, at most two batches wide:
  // its states 8 at a time in SIMD lanes, the undecided ones one by one. Raked: batch b takes
  // states lo + b, lo + b + stride, ... so each batch spans the range and a collision anywhere
  // shows up early.
  thread_local std::vector<Eigen::VectorXd> batch(kBatch);
  // far_in_batch: the first batch's last lane is the far end; one it leaves unproven (`proven`
  // false) gets a plain check before any other state.
  auto far_end_free = [&](bool proven) {
    int unused = 0;
    const bool blocked = !proven && !check(steps, 0, unused);
    far_end_was(blocked);
    return !blocked;
  };
  auto check_batch = [&](int lo, int hi, bool far) {
    const int size = hi - lo + 1, stride = (size + kBatch - 1) / kBatch;
    for (int b = 0; b < stride; ++b) {
      const double* q[kBatch];
      int idx[kBatch], count = 0;
      for (int i = lo + b; i <= hi; i += stride) {
        idx[count] = i;
        batch[std::size_t(count)].noalias() = seg.a + (i * seg.h) * seg.dir;  // into the buffer, no allocation
        q[count] = batch[std::size_t(count)].data();
        ++count;
      }
      const std::uint32_t proven = proven_free_(q, count, seg.dir, 0.0);
      int unused = 0;
      if (far && idx[count - 1] == steps) {
        if (!far_end_free(proven >> (count - 1) & 1u)) return false;
        --count;  // settled
      }
      for (int m = 0; m < count; ++m)
        if (!(proven >> m & 1u) && !check(idx[m], 0, unused)) return false;
    }
    return true;
  };
  thread_local std::vector<Range> queue;
  // A span batch: 8 lanes 2T + 1 states apart, each proving the T states on either side of it
  // (proven_free's reach), so one batch covers up to 8 (2T + 1) states. What lanes leave unproven
  // is queued for certified checks, with the range's estimate: neighbouring lanes' stretches as
  // one range, since one certificate often covers both (fewer certified checks than a range per
  // lane).
  auto check_span = [&](int lo, int hi, int e, int se, int T, bool far) {
    const double* q[kBatch];
    int idx[kBatch], count = 0;
    for (int i = lo + T; i - T <= hi && count < kBatch; i += 2 * T + 1) {
      idx[count] = std::min(i, hi);
      batch[std::size_t(count)].noalias() = seg.a + (idx[count] * seg.h) * seg.dir;
      q[count] = batch[std::size_t(count)].data();
      ++count;
    }
    const std::uint32_t proven = proven_free_(q, count, seg.dir, (T + 1e-6) * seg.h);
    if (far) {
      const bool lane = proven >> (count - 1) & 1u;
      if (!far_end_free(lane)) return false;
      if (!lane) hi = steps - 1;  // checked: the stretch left to certified checks stops short of it
    }
    for (int m = 0; m < count; ++m) {
      if (proven >> m & 1u) continue;
      int last = m;
      while (last + 1 < count && !(proven >> (last + 1) & 1u)) ++last;
      queue.push_back({std::max(lo, idx[m] - T), std::min(hi, idx[last] + T), e, se, true});
      m = last;
    }
    return true;
  };
  queue.assign(1, {1, far_in_batch ? steps : steps - 1 - k, k, span_k});  // (end_valid: k = 0, every state but the ends)
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto [lo, hi, e, se, certified_only] = queue[head];
    if (lo > hi) continue;
    const int size = hi - lo + 1;
    // Ranges from a plain far end (e = 0 with an estimate: the first range, and the stretches its
    // span batch's lanes leave) are raked only up to one batch: beyond, the first range takes one
    // span batch rather than two raked ones, a stretch certified checks (bench-paired: faster on
    // the bookshelf sets, level on the others).
    if (proven_free_ && e == 0 && size >= 2 && size <= (se > 0 ? kBatch : kBatchRange)) {
      if (!check_batch(lo, hi, far_in_batch && head == 0)) {
        ++invalid_;
        return false;
      }
      continue;
    }
    const int span = (size + kBatch - 1) / (2 * kBatch);  // the least T with 8 (2T + 1) >= size, for size > 8
    if (proven_free_ && !certified_only && size > kBatch && span * kSpanShare <= std::max(1, se)) {
      if (!check_span(lo, hi, e, se, span, far_in_batch && head == 0)) {
        ++invalid_;
        return false;
      }
      continue;
    }
    const int at = size > 2 * e + 1 && size <= 4 * e + 2 ? lo + e : (lo + hi) / 2;
    if (!check(at, need_of(std::max(at - lo, hi - at)), k, &span_k)) {
      ++invalid_;
      return false;
    }
    queue.push_back({lo, at - k - 1, k, span_k, certified_only});
    queue.push_back({at + k + 1, hi, k, span_k, certified_only});
  }
  ++valid_;
  return true;
}

void CertifiedMotionValidator::far_end_was(bool blocked) const {
  const std::uint32_t r = far_blocked_.load(std::memory_order_relaxed);
  far_blocked_.store(blocked ? r + (((1u << 16) - r) >> 5) : r - (r >> 5), std::memory_order_relaxed);
}

bool CertifiedMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2,
                                           std::pair<ob::State*, double>& last_valid) const {
  // Sequential from s1 so the last valid state is known; certified stretches are skipped too.
  const Segment seg(*si_, s1, s2);
  const int steps = seg.steps;
  double covered = 0;
  for (int i = 1; i <= steps; ++i) {
    const double t = i * seg.h;
    if (t <= covered && i < steps) continue;
    const double ahead = certificate_(seg.at(i), seg.dir, (steps - i + 1e-6) * seg.h).reach;
    if (ahead < 0) {
      last_valid.second = double(i - 1) / steps;
      if (last_valid.first) si_->getStateSpace()->interpolate(s1, s2, last_valid.second, last_valid.first);
      ++invalid_;
      return false;
    }
    covered = t + ahead;
  }
  ++valid_;
  return true;
}

}  // namespace dmgplace::runtime
