#include "dmgplace/runtime/motion/nearest_states.hpp"

#include <iostream>  // OMPL 1.5's GNAT header uses std::cout without including it
#include <ompl/datastructures/NearestNeighborsGNATNoThreadSafety.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "dmgplace/runtime/system/lanes.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::runtime {
namespace {
constexpr std::size_t kProbe = std::numeric_limits<std::size_t>::max();  // GNAT's query: query_
constexpr std::size_t kLanes = NearestStates::kBlock;
constexpr double kEmpty = 1e150;  // an unused lane's coordinate: its squared distance is ~1e300, never the nearest

// The scan over blocks of kLanes points (coordinate k of a block's points contiguous): a block's
// squared distances in two lanes::D vectors, then one comparison of its smallest with the best so
// far (most blocks hold no better point). Inlined into an AVX2 + FMA and a baseline entry point,
// so each is compiled for its own instruction set.
DMGPLACE_LANES_INLINE std::size_t scan(const double* blocks, std::size_t count, std::size_t dim, const double* q) {
  static_assert(kLanes == 2 * lanes::W);
  double best = std::numeric_limits<double>::infinity();
  std::size_t at = 0;
  const std::size_t nb = (count + kLanes - 1) / kLanes;
  for (std::size_t b = 0; b < nb; ++b) {
    const double* x = blocks + b * dim * kLanes;
    lanes::D lo{}, hi{};
    for (std::size_t k = 0; k < dim; ++k) {
      const lanes::D qk = lanes::splat(q[k]);
      const lanes::D tl = lanes::load(x + k * kLanes) - qk, th = lanes::load(x + k * kLanes + lanes::W) - qk;
      lo += tl * tl;
      hi += th * th;
    }
    const lanes::D m4 = lanes::min(lo, hi);
    const double m = std::min(std::min(m4[0], m4[1]), std::min(m4[2], m4[3]));
    if (!(m < best)) continue;
    best = m;
    for (int i = 0; i < lanes::W; ++i)
      if (lo[i] == m || hi[i] == m) {
        at = b * kLanes + std::size_t(lo[i] == m ? i : i + lanes::W);
        break;
      }
  }
  return at;
}
__attribute__((target("avx2,fma"))) std::size_t scan_avx2(const double* blocks, std::size_t count, std::size_t dim,
                                                          const double* q) {
  return scan(blocks, count, dim, q);
}
std::size_t scan_portable(const double* blocks, std::size_t count, std::size_t dim, const double* q) {
  return scan(blocks, count, dim, q);
}
}  // namespace

struct NearestStates::Gnat {
  ompl::NearestNeighborsGNATNoThreadSafety<std::size_t> nn;
};

NearestStates::NearestStates(std::size_t dim) : dim_(dim) {
  if (dim == 0) throw std::invalid_argument("NearestStates: dimension 0");
}

NearestStates::~NearestStates() = default;

double NearestStates::distance(std::size_t a, std::size_t b) const {
  const double* x = a == kProbe ? query_ : point(a);
  const double* y = b == kProbe ? query_ : point(b);
  double s = 0;
  for (std::size_t k = 0; k < dim_; ++k) s += (x[k] - y[k]) * (x[k] - y[k]);
  return std::sqrt(s);
}

std::size_t NearestStates::add(const double* q) {
  const std::size_t index = size();
  flat_.insert(flat_.end(), q, q + dim_);
  removed_.push_back(0);
  if (index % kLanes == 0) blocks_.resize(blocks_.size() + dim_ * kLanes, kEmpty);
  double* block = blocks_.data() + (index / kLanes) * dim_ * kLanes;
  for (std::size_t k = 0; k < dim_; ++k) block[k * kLanes + index % kLanes] = q[k];
  if (gnat_) {
    gnat_->nn.add(index);
  } else if (size() > kScan) {
    gnat_ = std::make_unique<Gnat>();
    gnat_->nn.setDistanceFunction([this](const std::size_t& a, const std::size_t& b) { return distance(a, b); });
    std::vector<std::size_t> all;
    for (std::size_t i = 0; i < size(); ++i)
      if (!removed_[i]) all.push_back(i);
    gnat_->nn.add(all);
  }
  return index;
}

void NearestStates::remove(std::size_t i) {
  if (i >= size()) throw std::out_of_range("NearestStates: remove of an index never added");
  if (removed_[i]) return;
  removed_[i] = 1;
  ++removed_count_;
  double* block = blocks_.data() + (i / kLanes) * dim_ * kLanes;
  for (std::size_t k = 0; k < dim_; ++k) block[k * kLanes + i % kLanes] = kEmpty;
}

std::size_t NearestStates::nearest(const double* q) const {
  if (removed_count_ >= size()) throw std::logic_error("NearestStates: nearest of an empty set");
  if (gnat_) {
    query_ = q;
    // GNAT keeps removed points (its own removal needs distinct points); when it answers with
    // one, the scan, which never sees them, decides.
    const std::size_t at = gnat_->nn.nearest(kProbe);
    if (!removed_[at]) return at;
  }
  return simd_path() == SimdPath::Avx2 ? scan_avx2(blocks_.data(), size(), dim_, q)
                                       : scan_portable(blocks_.data(), size(), dim_, q);
}

}  // namespace dmgplace::runtime
