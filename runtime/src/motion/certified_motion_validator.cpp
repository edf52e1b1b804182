#include "dmgplace/runtime/motion/certified_motion_validator.hpp"

#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <cmath>
#include <optional>
#include <vector>

namespace ob = ompl::base;

namespace dmgplace::runtime {
namespace {
constexpr int kLanes = 8;  // SphereFieldChecker::free_lanes' lanes
constexpr int kLaneRange =
    2 * kLanes;  // wider uncertified ranges are bisected (fewer states, when certificates return)
// A span lane check's lanes reach T states each way, where T x kSpanShare is within the neighbouring
// certificate: the lane check widens by a static speed bound, which lasts about half as far as a
// certificate's local one (bench-mbm: shares 1.5-2 best, smaller ones slower; docs/perf-log.md).
constexpr int kSpanShare = 2;
// Far ends go into the first lane check's last lane while fewer than this share of recent ones were
// blocked (CertifiedMotionValidator::far_blocked_). A blocked one then costs a lane check more than a
// plain check first; a free one the lane check proves costs nothing more. On the planners' median
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

// One check_motion call: the segment's states, checked far end first, then its unchecked ranges
// bisected breadth first as OMPL's discrete validator does, minus what each checked state
// certifies around itself (a certificate is symmetric: state i proves states i-k .. i+k), with
// lane checks of states in SIMD lanes where the validator has them (proven_free_).
struct CertifiedMotionValidator::Call {
  // An unchecked index range [lo, hi] (state 0 is valid by contract), with an estimate e of the
  // next certificate (that of the check that made it) and the same certificate's under isotropic
  // bounds (Certificate::estimate) for span lane checks.
  struct Range {
    int lo, hi, estimate, span_estimate;
    bool certified_only = false;  // a span lane check's lane left it: certified checks from here on
  };
  const CertifiedMotionValidator& v;
  const Segment seg;
  const int steps;
  // far_in_lanes: the first lane check's last lane takes the far end; one it leaves unproven gets a
  // plain check before any other state (far_end_free).
  bool far_in_lanes = false;

  Call(const CertifiedMotionValidator& validator, const ob::State* s1, const ob::State* s2)
      : v(validator), seg(*validator.si_, s1, s2), steps(seg.steps) {}

  static std::vector<Eigen::VectorXd>& lanes() {
    thread_local std::vector<Eigen::VectorXd> states(kLanes);
    return states;
  }
  static std::vector<Range>& queue() {
    thread_local std::vector<Range> q;
    return q;
  }

  // State i's certificate, asked to reach `need` steps on either side (0: a plain check, no
  // certificate work). k: the states it covers each way; `span_k` (optional): its estimate's.
  bool check(int i, int need, int& k, int* span_k = nullptr) const {
    const Certificate c = v.certificate_(seg.at(i), seg.dir, need > 0 ? (need + 1e-6) * seg.h : 0.0);
    if (c.reach < 0) return false;
    auto states = [&](double t) { return seg.h > 0 ? int(std::min(t / seg.h, double(steps))) : steps; };
    k = states(c.reach);
    if (span_k) *span_k = std::min(k, states(c.estimate));
    return true;
  }
  // With lane proofs a certificate need only reach a lane check's width: what lies beyond goes to span
  // lane checks, which take it as their estimate (refining further made bisection midpoints the
  // costliest checks).
  int need_of(int states) const { return v.proven_free_ ? std::min(states, kLanes) : states; }

  bool far_end_free(bool proven) const {
    int unused = 0;
    const bool blocked = !proven && !check(steps, 0, unused);
    v.far_end_was(blocked);
    return !blocked;
  }

  // A range the last certificate did not reach beyond its own state, at most two lane checks wide:
  // its states 8 at a time in SIMD lanes, the undecided ones one by one. Raked: lane check b takes
  // states lo + b, lo + b + stride, ... so each lane check spans the range and a collision anywhere
  // shows up early.
  bool check_lanes(int lo, int hi, bool far) const {
    auto& states = lanes();
    const int size = hi - lo + 1, stride = (size + kLanes - 1) / kLanes;
    for (int b = 0; b < stride; ++b) {
      const double* q[kLanes];
      int idx[kLanes], count = 0;
      for (int i = lo + b; i <= hi; i += stride) {
        idx[count] = i;
        states[std::size_t(count)].noalias() = seg.a + (i * seg.h) * seg.dir;  // into the buffer, no allocation
        q[count] = states[std::size_t(count)].data();
        ++count;
      }
      const std::uint32_t proven = v.proven_free_(q, count, seg.dir, 0.0);
      int unused = 0;
      if (far && idx[count - 1] == steps) {
        if (!far_end_free(proven >> (count - 1) & 1u)) return false;
        --count;  // settled
      }
      for (int m = 0; m < count; ++m)
        if (!(proven >> m & 1u) && !check(idx[m], 0, unused)) return false;
    }
    return true;
  }

  // A span lane check: 8 lanes 2T + 1 states apart, each proving the T states on either side of it
  // (proven_free's reach), so one lane check covers up to 8 (2T + 1) states. What lanes leave unproven
  // is queued for certified checks, with the range's estimate: neighbouring lanes' stretches as
  // one range, since one certificate often covers both.
  bool check_span(int lo, int hi, int e, int se, int T, bool far) const {
    auto& states = lanes();
    const double* q[kLanes];
    int idx[kLanes], count = 0;
    for (int i = lo + T; i - T <= hi && count < kLanes; i += 2 * T + 1) {
      idx[count] = std::min(i, hi);
      states[std::size_t(count)].noalias() = seg.a + (idx[count] * seg.h) * seg.dir;
      q[count] = states[std::size_t(count)].data();
      ++count;
    }
    const std::uint32_t proven = v.proven_free_(q, count, seg.dir, (T + 1e-6) * seg.h);
    if (far) {
      const bool lane = proven >> (count - 1) & 1u;
      if (!far_end_free(lane)) return false;
      if (!lane) hi = steps - 1;  // checked: the stretch left to certified checks stops short of it
    }
    for (int m = 0; m < count; ++m) {
      if (proven >> m & 1u) continue;
      int last = m;
      while (last + 1 < count && !(proven >> (last + 1) & 1u)) ++last;
      queue().push_back({std::max(lo, idx[m] - T), std::min(hi, idx[last] + T), e, se, true});
      m = last;
    }
    return true;
  }

  // The far end first: a bad goal is found at once. With lane proofs a plain check, and span
  // lane checks take the whole motion from there; where far ends are seldom blocked, not even that:
  // the first lane check's last lane takes it (far_in_lanes). Returns the first range, or none when
  // the far end is blocked.
  std::optional<Range> far_end(bool end_valid) {
    int k = 0, span_k = 0;
    if (!end_valid && v.proven_free_ && steps > 1 &&
        v.far_blocked_.load(std::memory_order_relaxed) < std::uint32_t(kFarLaneBlockedShare * 65536.0)) {
      far_in_lanes = true;
      span_k = steps;
    } else if (!end_valid) {
      if (!check(steps, v.proven_free_ ? 0 : steps - 1, k, &span_k)) {
        v.far_end_was(true);
        return std::nullopt;
      }
      v.far_end_was(false);
      if (v.proven_free_) k = 0, span_k = steps;
    }
    return Range{1, far_in_lanes ? steps : steps - 1 - k, k, span_k};  // (end_valid: k = 0, every state but the ends)
  }

  // One range off the queue: raked lane checks, a span lane check, or a check that splits it in two (a
  // range a little wider than one certificate, 2e + 1 < size <= 4e + 2, is tiled from its left
  // end rather than split in the middle). False when a state is in collision.
  bool step(const Range& r, bool first) {
    const auto [lo, hi, e, se, certified_only] = r;
    if (lo > hi) return true;
    const int size = hi - lo + 1;
    // Ranges from a plain far end (e = 0 with an estimate: the first range, and the stretches its
    // span lane check's lanes leave) are raked only up to one lane check: beyond, the first range takes one
    // span lane check rather than two raked ones, a stretch certified checks.
    if (v.proven_free_ && e == 0 && size >= 2 && size <= (se > 0 ? kLanes : kLaneRange))
      return check_lanes(lo, hi, far_in_lanes && first);
    const int span = (size + kLanes - 1) / (2 * kLanes);  // the least T with 8 (2T + 1) >= size, for size > 8
    if (v.proven_free_ && !certified_only && size > kLanes && span * kSpanShare <= std::max(1, se))
      return check_span(lo, hi, e, se, span, far_in_lanes && first);
    const int at = size > 2 * e + 1 && size <= 4 * e + 2 ? lo + e : (lo + hi) / 2;
    int k = 0, span_k = 0;
    if (!check(at, need_of(std::max(at - lo, hi - at)), k, &span_k)) return false;
    queue().push_back({lo, at - k - 1, k, span_k, certified_only});
    queue().push_back({at + k + 1, hi, k, span_k, certified_only});
    return true;
  }

  bool run(bool end_valid) {
    const auto first = far_end(end_valid);
    if (!first) return false;
    auto& q = queue();
    q.assign(1, *first);
    for (std::size_t head = 0; head < q.size(); ++head)
      if (!step(Range(q[head]), head == 0)) return false;  // a copy: step() may grow the queue
    return true;
  }
};

bool CertifiedMotionValidator::check_motion(const ob::State* s1, const ob::State* s2, bool end_valid) const {
  Call call(*this, s1, s2);
  if (!call.run(end_valid)) {
    ++invalid_;
    return false;
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
