#include "dmgplace/runtime/motion/nearest_states.hpp"

#include <iostream>  // OMPL 1.5's GNAT header uses std::cout without including it
#include <ompl/datastructures/NearestNeighborsGNATNoThreadSafety.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace dmgplace::runtime {
namespace {
constexpr std::size_t kProbe = std::numeric_limits<std::size_t>::max();  // GNAT's query: query_
}

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
  if (gnat_) {
    gnat_->nn.add(index);
  } else if (size() > kScan) {
    gnat_ = std::make_unique<Gnat>();
    gnat_->nn.setDistanceFunction([this](const std::size_t& a, const std::size_t& b) { return distance(a, b); });
    std::vector<std::size_t> all(size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    gnat_->nn.add(all);
  }
  return index;
}

std::size_t NearestStates::nearest(const double* q) const {
  if (flat_.empty()) throw std::logic_error("NearestStates: nearest of an empty set");
  if (gnat_) {
    query_ = q;
    return gnat_->nn.nearest(kProbe);
  }
  double best = std::numeric_limits<double>::infinity();
  std::size_t at = 0;
  for (std::size_t i = 0, n = size(); i < n; ++i) {
    const double* x = point(i);
    double s = 0;
    for (std::size_t k = 0; k < dim_; ++k) s += (x[k] - q[k]) * (x[k] - q[k]);
    if (s < best) {
      best = s;
      at = i;
    }
  }
  return at;
}

}  // namespace dmgplace::runtime
