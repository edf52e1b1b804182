#pragma once
// The nearest stored point by Euclidean distance, for the planner's trees. Up to kScan points a
// flat scan by squared distance; past that OMPL's GNAT, built from the points at once. Measured in
// 7-D with uniform queries: GNAT (through its std::function metric) took 2.5x a plain scan's
// time at 256 points and 1.4x at 4096, and won only beyond about 10k.
#include <cstddef>
#include <memory>
#include <vector>

namespace dmgplace::runtime {

class NearestStates {
 public:
  static constexpr std::size_t kScan = 2048;
  explicit NearestStates(std::size_t dim);
  ~NearestStates();
  NearestStates(const NearestStates&) = delete;
  NearestStates& operator=(const NearestStates&) = delete;

  // Stores q (dim values); returns its index (0, 1, ...).
  std::size_t add(const double* q);
  // Index of the stored point nearest to q; the set must not be empty.
  std::size_t nearest(const double* q) const;
  std::size_t size() const { return flat_.size() / dim_; }
  const double* point(std::size_t i) const { return flat_.data() + i * dim_; }

 private:
  struct Gnat;  // OMPL's GNAT over indices (not in this header: the installed headers name no OMPL type)
  double distance(std::size_t a, std::size_t b) const;
  std::size_t dim_;
  std::vector<double> flat_;  // one row per point
  std::unique_ptr<Gnat> gnat_;
  mutable const double* query_ = nullptr;  // the point GNAT's probe index stands for
};

}  // namespace dmgplace::runtime
