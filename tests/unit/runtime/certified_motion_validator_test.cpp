// The certified motion validator checks a subset of the discrete validator's states and proves
// the rest free, so both must give the same answer on every motion, with fewer checks in open space.
#include <gtest/gtest.h>

#include <ompl/base/DiscreteMotionValidator.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "dmgplace/runtime/motion/certified_motion_validator.hpp"

namespace ob = ompl::base;
using dmgplace::runtime::CertifiedMotionValidator;

namespace {
struct Disc {
  double x, y, r;
};
const std::vector<Disc> kDiscs = {{3, 3, 1}, {6, 7, 1.5}, {7, 2, 0.5}, {2, 8, 0.8}};

double clearance(double x, double y) {
  double c = 1e9;
  for (const auto& d : kDiscs) c = std::min(c, std::hypot(x - d.x, y - d.y) - d.r);
  return c;
}

ob::SpaceInformationPtr make_space(std::atomic<long>* checks) {
  auto space = std::make_shared<ob::RealVectorStateSpace>(2);
  space->setBounds(0, 10);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker([checks](const ob::State* s) {
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    ++*checks;
    return clearance(v->values[0], v->values[1]) > 0;
  });
  si->setStateValidityCheckingResolution(0.001);
  si->setup();
  return si;
}

// A random motion a -> b from a valid start.
void random_motion(std::mt19937_64& rng, ob::ScopedState<>& a, ob::ScopedState<>& b) {
  std::uniform_real_distribution<double> u(0, 10);
  do {
    a[0] = u(rng);
    a[1] = u(rng);
  } while (clearance(a[0], a[1]) <= 0);
  b[0] = u(rng);
  b[1] = u(rng);
}

// 3000 random motions from valid starts: the certified validator gives the discrete one's answer
// to each (a failed expectation names the motion). Returns how many were invalid.
int discrete_answers(const ob::SpaceInformationPtr& si, ob::DiscreteMotionValidator& discrete,
                     CertifiedMotionValidator& certified, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  ob::ScopedState<> a(si), b(si);
  int invalid = 0;
  for (int i = 0; i < 3000; ++i) {
    random_motion(rng, a, b);
    const bool d = discrete.checkMotion(a.get(), b.get()), c = certified.checkMotion(a.get(), b.get());
    EXPECT_EQ(c, d) << "motion (" << a[0] << ", " << a[1] << ") -> (" << b[0] << ", " << b[1] << ")";
    if (c != d) break;  // one named motion is enough
    invalid += !d;
  }
  return invalid;
}

// Which stretches of the current motion the checks proved free, recorded from a certified
// validator's callbacks as intervals of the motion's parameter: certificates at half the
// clearance, a third of clear lanes left undecided, so ranges are cut up and neighbouring span
// lanes fail together. Also counts the checks, and those at the motion's far end.
struct ProofRecorder {
  Eigen::Vector2d start, unit;
  double length = 0, step = 0;
  std::vector<std::pair<double, double>> proven;
  std::uint64_t salt = 0;
  long merged_lanes = 0, calls = 0, far_end_checks = 0;

  double along(const double* q) const { return (Eigen::Vector2d(q[0], q[1]) - start).dot(unit); }
  void note(const double* q) {
    ++calls;
    far_end_checks += std::abs(along(q) - length) < 1e-9;
  }
  CertifiedMotionValidator::FreeDistanceFn certificate() {
    return [this](const Eigen::VectorXd& q, const Eigen::VectorXd&, double) {
      note(q.data());
      const double c = clearance(q[0], q[1]);
      if (c <= 0) return -1.0;
      const double t = along(q.data());
      proven.push_back({t - c / 2, t + c / 2});
      return c / 2;
    };
  }
  CertifiedMotionValidator::ProvenFreeFn proven_free() {
    return [this](const double* const* q, int count, const Eigen::VectorXd&, double reach) {
      std::uint32_t mask = 0;
      for (int k = 0; k < count; ++k) {
        note(q[k]);
        const bool sure = clearance(q[k][0], q[k][1]) > reach + 1e-9 && (++salt * 0x9E3779B97F4A7C15ull >> 61) % 3 != 0;
        if (!sure) continue;
        mask |= 1u << k;
        const double t = along(q[k]);
        proven.push_back({t - reach, t + reach});
      }
      for (int k = 0; k + 1 < count; ++k) merged_lanes += reach > 0 && !(mask >> k & 3u);
      return mask;
    };
  }
  // A new motion a -> b (the validator's resolution `step`).
  void begin(const ob::ScopedState<>& a, const ob::ScopedState<>& b) {
    start = Eigen::Vector2d(a[0], a[1]);
    const Eigen::Vector2d d = Eigen::Vector2d(b[0], b[1]) - start;
    length = d.norm();
    unit = d / length;
    proven.clear();
  }
  int steps() const { return std::max(1, int(std::ceil(length / step))); }
  // The first of states first..last (1 .. steps()) no check proved, or 0.
  int unproven(int first, int last) const {
    for (int s = first; s <= last; ++s) {
      const double t = length * s / steps();
      if (!std::any_of(proven.begin(), proven.end(),
                       [&](const auto& in) { return in.first - 1e-9 <= t && t <= in.second + 1e-9; }))
        return s;
    }
    return 0;
  }
};
}  // namespace

TEST(CertifiedMotionValidator, AgreesWithTheDiscreteValidatorOnEveryMotionWithFewerChecks) {
  std::atomic<long> discrete_checks{0}, certified_checks{0};
  auto si = make_space(&discrete_checks);
  ob::DiscreteMotionValidator discrete(si);
  // A point robot moves 1 m per unit of motion: its clearance is the certified free distance.
  CertifiedMotionValidator certified(si, [&](const Eigen::VectorXd& q, const Eigen::VectorXd&, double) {
    ++certified_checks;
    const double c = clearance(q[0], q[1]);
    return c > 0 ? c : -1.0;
  });
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 10);
  ob::ScopedState<> a(si), b(si);
  int valid = 0, invalid = 0;
  for (int i = 0; i < 3000; ++i) {
    do {
      a[0] = u(rng);
      a[1] = u(rng);
    } while (clearance(a[0], a[1]) <= 0);  // checkMotion assumes a valid first state
    b[0] = u(rng);
    b[1] = u(rng);
    const bool d = discrete.checkMotion(a.get(), b.get());
    const bool c = certified.checkMotion(a.get(), b.get());
    ASSERT_EQ(c, d) << "motion (" << a[0] << ", " << a[1] << ") -> (" << b[0] << ", " << b[1] << ")";
    (d ? valid : invalid)++;
    std::pair<ob::State*, double> last{nullptr, 0};
    ASSERT_EQ(certified.checkMotion(a.get(), b.get(), last), d);
    if (!d) {
      // The reported last valid fraction is valid, and the next discrete step is not far behind.
      ob::ScopedState<> x(si);
      si->getStateSpace()->interpolate(a.get(), b.get(), last.second, x.get());
      EXPECT_GT(clearance(x[0], x[1]), 0);
    }
  }
  EXPECT_GT(valid, 300);
  EXPECT_GT(invalid, 300);
  // Same answers from a fraction of the checks (both validators counted over the same motions).
  EXPECT_LT(certified_checks.load() * 5, discrete_checks.load());
  RecordProperty("discrete_checks", int(discrete_checks.load()));
  RecordProperty("certified_checks", int(certified_checks.load()));
}

// With lane proofs: near the discs the checker certifies nothing (as the sphere layer when the
// exact layer had to decide), so short uncertified ranges go to the lane check, which proves only
// states well clear of the discs and leaves the rest undecided. The answers stay the discrete ones.
TEST(CertifiedMotionValidator, LaneProofsOfUncertifiedRangesKeepTheDiscreteAnswers) {
  std::atomic<long> discrete_checks{0};
  auto si = make_space(&discrete_checks);
  ob::DiscreteMotionValidator discrete(si);
  long lane_checks = 0, proven = 0, undecided = 0;
  CertifiedMotionValidator certified(
      si,
      [&](const Eigen::VectorXd& q, const Eigen::VectorXd&, double) {
        const double c = clearance(q[0], q[1]);
        return c <= 0 ? -1.0 : c < 0.3 ? 0.0 : c;
      },
      [&](const double* const* q, int count, const Eigen::VectorXd&, double reach) {
        EXPECT_GE(count, 1);
        EXPECT_LE(count, 8);
        ++lane_checks;
        std::uint32_t mask = 0;
        for (int k = 0; k < count; ++k) {
          // Some clear lanes left undecided too; a span lane must be clear by its reach.
          const bool sure = clearance(q[k][0], q[k][1]) > reach + 0.01 && (k % 3 != 1);
          mask |= std::uint32_t(sure) << k;
          (sure ? proven : undecided)++;
        }
        return mask;
      });
  EXPECT_GT(discrete_answers(si, discrete, certified, 5), 300);
  EXPECT_GT(lane_checks, 1000) << "the lane path must be exercised";
  EXPECT_GT(proven, 0);
  EXPECT_GT(undecided, 0);
}

// Span lane checks: where certificates reach far, a range goes to one lane check whose lanes each prove
// the states within `reach` of them (the point robot's clearance must exceed it: it moves 1 m per
// unit of motion), some clear lanes left undecided; what a lane leaves, certified checks settle.
// The answers stay the discrete ones, and span lane checks do part of the work.
TEST(CertifiedMotionValidator, SpanChecksKeepTheDiscreteAnswers) {
  std::atomic<long> discrete_checks{0};
  auto si = make_space(&discrete_checks);
  ob::DiscreteMotionValidator discrete(si);
  long spans = 0, span_lanes = 0, span_proven = 0, certified_checks = 0;
  CertifiedMotionValidator certified(
      si,
      [&](const Eigen::VectorXd& q, const Eigen::VectorXd&, double) {
        ++certified_checks;
        const double c = clearance(q[0], q[1]);
        return c > 0 ? c : -1.0;
      },
      [&](const double* const* q, int count, const Eigen::VectorXd& direction, double reach) {
        EXPECT_GE(count, 1);
        EXPECT_LE(count, 8);
        EXPECT_NEAR(direction.norm(), 1.0, 1e-9);
        spans += reach > 0;
        std::uint32_t mask = 0;
        for (int k = 0; k < count; ++k) {
          const bool sure = clearance(q[k][0], q[k][1]) > reach + 0.01 && (k % 3 != 1);
          mask |= std::uint32_t(sure) << k;
          if (reach > 0) span_lanes++, span_proven += sure;
        }
        return mask;
      });
  EXPECT_GT(discrete_answers(si, discrete, certified, 7), 300);
  EXPECT_GT(spans, 1000) << "span lane checks must be exercised";
  EXPECT_GT(span_proven, 0);
  EXPECT_LT(span_proven, span_lanes) << "some span lanes must be left to certified checks";
  RecordProperty("span_checks", int(spans));
  RecordProperty("certified_checks", int(certified_checks));
}

// Every state of a valid motion is proven by some check: a certificate around a checked state, a
// span lane's reach, a plain check or a lane. Recorded from the callbacks as intervals of
// the motion's parameter, with certificates at half the clearance and a third of clear lanes left
// undecided, so ranges are cut up and neighbouring span lanes fail together (their stretches
// are handed on as one range): a state dropped anywhere fails here, whatever the geometry.
TEST(CertifiedMotionValidator, EveryStateOfAValidMotionIsProvenBySomeCheck) {
  std::atomic<long> discrete_checks{0};
  auto si = make_space(&discrete_checks);
  ProofRecorder rec;
  rec.step = si->getStateSpace()->getLongestValidSegmentLength();
  CertifiedMotionValidator certified(si, rec.certificate(), rec.proven_free());
  std::mt19937_64 rng(11);
  ob::ScopedState<> a(si), b(si);
  int valid = 0;
  for (int i = 0; i < 3000; ++i) {
    random_motion(rng, a, b);
    rec.begin(a, b);
    if (!certified.checkMotion(a.get(), b.get())) continue;
    ++valid;
    const int s = rec.unproven(1, rec.steps());
    ASSERT_EQ(s, 0) << "state " << s << " of " << rec.steps() << " unproven on (" << a[0] << ", " << a[1] << ") -> ("
                    << b[0] << ", " << b[1] << ")";
  }
  EXPECT_GT(valid, 300);
  EXPECT_GT(rec.merged_lanes, 1000) << "neighbouring span lanes must fail together";
  RecordProperty("valid_motions", valid);
}

// checkMotionBetweenValid (shortcut jumps, the straight line between roots): on motions whose both
// ends are valid, the discrete validator's answer every time; the far end is never checked, and
// on each valid motion every other state is proven by some check (certificates at half the
// clearance, a third of clear lanes left undecided, so ranges, lane checks and spans all take part).
TEST(CertifiedMotionValidator, BetweenValidEndsKeepsTheDiscreteAnswersAndSkipsTheFarEnd) {
  std::atomic<long> discrete_checks{0};
  auto si = make_space(&discrete_checks);
  ob::DiscreteMotionValidator discrete(si);
  ProofRecorder rec;
  rec.step = si->getStateSpace()->getLongestValidSegmentLength();
  CertifiedMotionValidator certified(si, rec.certificate(), rec.proven_free());
  std::mt19937_64 rng(19);
  ob::ScopedState<> a(si), b(si);
  int valid = 0, invalid = 0;
  for (int i = 0; i < 3000; ++i) {
    do random_motion(rng, a, b);
    while (clearance(b[0], b[1]) <= 0);
    rec.begin(a, b);
    const bool c = certified.checkMotionBetweenValid(a.get(), b.get());
    ASSERT_EQ(c, discrete.checkMotion(a.get(), b.get()))
        << "motion (" << a[0] << ", " << a[1] << ") -> (" << b[0] << ", " << b[1] << ")";
    (c ? valid : invalid)++;
    if (!c) continue;
    const int s = rec.unproven(1, rec.steps() - 1);  // (the far end is valid by contract)
    ASSERT_EQ(s, 0) << "state " << s << " of " << rec.steps() << " unproven on (" << a[0] << ", " << a[1] << ") -> ("
                    << b[0] << ", " << b[1] << ")";
  }
  EXPECT_GT(valid, 300);
  EXPECT_GT(invalid, 300);
  EXPECT_GT(rec.calls, 10000);
  EXPECT_EQ(rec.far_end_checks, 0) << "the far end is known valid";
}

// A certificate's estimate (how far a span lane check's static widening would reach there), not its
// reach, decides whether a span lane check is tried next to it: between two valid states (where the
// motion does not start with the far end's plain check and a span lane check over all of it), an
// estimate of 0 never brings one, a quarter of the reach fewer than the whole reach; the answers
// stay the discrete ones throughout.
TEST(CertifiedMotionValidator, SpanChecksFollowTheCertificatesEstimate) {
  std::atomic<long> discrete_checks{0};
  auto si = make_space(&discrete_checks);
  ob::DiscreteMotionValidator discrete(si);
  auto spans_with = [&](double share) {
    long spans = 0;
    CertifiedMotionValidator certified(
        si, CertifiedMotionValidator::CertificateFn([&](const Eigen::VectorXd& q, const Eigen::VectorXd&, double) {
          const double c = clearance(q[0], q[1]);
          return c > 0 ? CertifiedMotionValidator::Certificate{c, share * c}
                       : CertifiedMotionValidator::Certificate{-1.0, -1.0};
        }),
        [&](const double* const* q, int count, const Eigen::VectorXd&, double reach) {
          spans += reach > 0;
          std::uint32_t mask = 0;
          for (int k = 0; k < count; ++k) mask |= std::uint32_t(clearance(q[k][0], q[k][1]) > reach + 0.01) << k;
          return mask;
        });
    std::mt19937_64 rng(13);
    ob::ScopedState<> a(si), b(si);
    int invalid = 0;
    for (int i = 0; i < 3000; ++i) {
      do random_motion(rng, a, b);
      while (clearance(b[0], b[1]) <= 0);
      const bool d = discrete.checkMotion(a.get(), b.get()), c = certified.checkMotionBetweenValid(a.get(), b.get());
      EXPECT_EQ(c, d) << "estimate share " << share << ", motion (" << a[0] << ", " << a[1] << ") -> (" << b[0] << ", "
                      << b[1] << ")";
      if (c != d) break;
      invalid += !d;
    }
    EXPECT_GT(invalid, 300) << "estimate share " << share;
    return spans;
  };
  const long none = spans_with(0.0), quarter = spans_with(0.25), whole = spans_with(1.0);
  EXPECT_EQ(none, 0);
  EXPECT_GT(quarter, 0);
  EXPECT_LT(quarter, whole);
  RecordProperty("span_checks", std::to_string(quarter) + " of " + std::to_string(whole));
}

// With lane proofs a motion's far end, where it gets a check at all, gets a plain one (the
// certificate asked for nothing, `enough` 0), since span lane checks take the whole motion; without
// them every far end's certificate is asked to reach the whole motion. The answers are the
// discrete ones either way.
TEST(CertifiedMotionValidator, FarEndIsAPlainCheckWhereLaneChecksTakeTheMotion) {
  std::atomic<long> discrete_checks{0};
  auto si = make_space(&discrete_checks);
  ob::DiscreteMotionValidator discrete(si);
  long spans = 0;
  auto far_end_needs = [&](bool lane_checks) {
    std::vector<double> needs;  // `enough` of each check of a motion's far end
    Eigen::Vector2d far;
    CertifiedMotionValidator::ProvenFreeFn proven;
    if (lane_checks)
      proven = [&spans](const double* const* q, int count, const Eigen::VectorXd&, double reach) {
        spans += reach > 0;
        std::uint32_t mask = 0;
        for (int k = 0; k < count; ++k) mask |= std::uint32_t(clearance(q[k][0], q[k][1]) > reach + 0.01) << k;
        return mask;
      };
    CertifiedMotionValidator certified(
        si,
        CertifiedMotionValidator::CertificateFn([&](const Eigen::VectorXd& q, const Eigen::VectorXd&, double enough) {
          if ((q - far).norm() < 1e-9) needs.push_back(enough);
          const double c = clearance(q[0], q[1]);
          return c > 0 ? CertifiedMotionValidator::Certificate{c / 2, c / 2}
                       : CertifiedMotionValidator::Certificate{-1.0, -1.0};
        }),
        proven);
    std::mt19937_64 rng(17);
    ob::ScopedState<> a(si), b(si);
    for (int i = 0; i < 2000; ++i) {
      random_motion(rng, a, b);
      far = Eigen::Vector2d(b[0], b[1]);
      const bool c = certified.checkMotion(a.get(), b.get()), d = discrete.checkMotion(a.get(), b.get());
      EXPECT_EQ(c, d) << "motion (" << a[0] << ", " << a[1] << ") -> (" << b[0] << ", " << b[1] << ")";
      if (c != d) break;
    }
    EXPECT_LE(needs.size(), 2000u) << "a far end is checked at most once";
    return needs;
  };
  const auto with = far_end_needs(true), without = far_end_needs(false);
  for (const double need : with) EXPECT_EQ(need, 0.0) << "with lane checks";
  EXPECT_GT(with.size(), 1000u) << "far ends are often blocked here: most get a plain check first";
  for (const double need : without) EXPECT_GT(need, 0.0) << "without lane checks";
  EXPECT_EQ(without.size(), 2000u);
  EXPECT_GT(spans, 1000) << "span lane checks take the motions from their far ends (estimates are half the reach)";
}

// In the open (every lane proven), a motion goes to lane checks by its size, never to a certified
// check. While its far ends have been blocked (a fresh validator assumes half are), the far end
// first gets a plain check and the interior up to 8 states one raked lane check (no reach), 9-16
// states one span lane check (reach 1 state), more one span lane check of a wider reach. Once far ends are
// seldom blocked, the far end is the first lane check's last lane: no plain check, and the same sizes
// count the far end in.
TEST(CertifiedMotionValidator, AMotionGoesToOneLaneCheckInTheOpen) {
  std::atomic<long> checks{0};
  auto si = make_space(&checks);
  const double h = si->getStateSpace()->getLongestValidSegmentLength();
  long raked = 0, spans = 0, certified = 0, far_ends = 0;
  double reach = 0;
  auto make = [&] {
    return std::make_unique<CertifiedMotionValidator>(
        si, CertifiedMotionValidator::CertificateFn([&](const Eigen::VectorXd&, const Eigen::VectorXd&, double enough) {
          (enough > 0 ? certified : far_ends) += 1;
          return CertifiedMotionValidator::Certificate{100.0, 100.0};
        }),
        [&](const double* const*, int count, const Eigen::VectorXd&, double r) {
          (r > 0 ? spans : raked) += 1;
          reach = r;
          return count >= 32 ? ~0u : (1u << count) - 1;
        });
  };
  ob::ScopedState<> a(si), b(si);
  auto motion = [&](CertifiedMotionValidator& validator, int steps) {
    raked = spans = certified = far_ends = 0;
    a[0] = 1;
    a[1] = 1;
    b[0] = 1 + (steps - 0.5) * h;  // `steps` states of the discrete validator
    b[1] = 1;
    EXPECT_TRUE(validator.checkMotion(a.get(), b.get()));
  };
  auto checks_by_size = [&](int states, int steps) {
    EXPECT_EQ(certified, 0) << steps << " steps";
    EXPECT_EQ(raked, states <= 8 ? 1 : 0) << steps << " steps";
    EXPECT_EQ(spans, states <= 8 ? 0 : 1) << steps << " steps";
    if (states > 8 && states <= 16) {
      EXPECT_NEAR(reach / ((b[0] - a[0]) / steps), 1.0, 1e-5) << steps << " steps";
    }
  };
  for (int steps = 3; steps <= 60; ++steps) {
    auto fresh = make();
    motion(*fresh, steps);
    EXPECT_EQ(far_ends, 1) << steps << " steps";
    checks_by_size(steps - 1, steps);
  }
  auto seasoned = make();
  for (int i = 0; i < 200; ++i) motion(*seasoned, 40);
  for (int steps = 3; steps <= 60; ++steps) {
    motion(*seasoned, steps);
    EXPECT_EQ(far_ends, 0) << steps << " steps";
    checks_by_size(steps, steps);
  }
}

// Where far ends are seldom blocked they go to the first lane check, and a far end its lane leaves
// unproven gets a plain check before any other state; where they are often blocked, a plain check
// first again. The answers are the discrete ones throughout.
TEST(CertifiedMotionValidator, FarEndsGoToTheFirstLaneCheckWhereSeldomBlocked) {
  std::atomic<long> checks{0};
  auto si = make_space(&checks);
  ob::DiscreteMotionValidator discrete(si);
  Eigen::Vector2d far;
  int calls = 0;  // certificate calls of the current motion
  int far_first = 0, far_later = 0, far_in_lane = 0;
  std::mt19937_64 lanes(5);
  CertifiedMotionValidator certified(
      si, CertifiedMotionValidator::CertificateFn([&](const Eigen::VectorXd& q, const Eigen::VectorXd&, double) {
        if ((q - far).norm() < 1e-9) (calls == 0 ? far_first : far_later) += 1;
        ++calls;
        const double c = clearance(q[0], q[1]);
        return c > 0 ? CertifiedMotionValidator::Certificate{c / 2, c / 2}
                     : CertifiedMotionValidator::Certificate{-1.0, -1.0};
      }),
      [&](const double* const* q, int count, const Eigen::VectorXd&, double reach) {
        std::uint32_t mask = 0;  // a quarter of clear lanes left undecided
        for (int k = 0; k < count; ++k)
          if (clearance(q[k][0], q[k][1]) > reach + 0.01 && lanes() % 4 != 0) {
            mask |= 1u << k;
            far_in_lane += (Eigen::Vector2d(q[k][0], q[k][1]) - far).norm() < 1e-9;
          }
        return mask;
      });
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1, 1);
  ob::ScopedState<> a(si), b(si);
  // Motions up to 1.4 long (a planner's extensions), `blocked`: far ends inside a disc, else in
  // the free space.
  auto run = [&](int count, bool blocked) {
    far_first = far_later = far_in_lane = 0;
    for (int i = 0; i < count; ++i) {
      do {
        random_motion(rng, a, b);
        b[0] = std::clamp(a[0] + u(rng), 0.0, 10.0);
        b[1] = std::clamp(a[1] + u(rng), 0.0, 10.0);
      } while ((clearance(b[0], b[1]) <= 0) != blocked);
      far = Eigen::Vector2d(b[0], b[1]);
      calls = 0;
      const bool c = certified.checkMotion(a.get(), b.get()), d = discrete.checkMotion(a.get(), b.get());
      EXPECT_EQ(c, d) << "motion (" << a[0] << ", " << a[1] << ") -> (" << b[0] << ", " << b[1] << ")";
      if (c != d) return;
    }
  };
  run(1, false);
  EXPECT_EQ(far_first, 1) << "a fresh validator checks the far end first";
  run(200, false);  // free far ends: into the lane check from the first few dozen on
  run(500, false);
  EXPECT_GT(far_in_lane, 150) << "lanes prove many far ends";
  EXPECT_GT(far_first, 50) << "a far end a lane leaves unproven is checked first";
  EXPECT_EQ(far_later, 0);
  run(100, true);  // blocked far ends: found by their plain checks, first
  EXPECT_EQ(far_first, 100);
  run(50, false);
  EXPECT_EQ(far_in_lane, 0) << "after a run of blocked far ends, plain checks first again";
  EXPECT_EQ(far_first, 50);
}
