#pragma once
// The nearest stored point by Euclidean distance, for the planner's trees. Up to kScan points a
// scan by squared distance over blocks of 8 points laid out coordinate by coordinate, in SIMD lanes
// (AVX2 + FMA when the CPU has them, simd_dispatch.hpp); past that OMPL's GNAT, built from the
// points at once. Up to kScan points the scan is faster than GNAT, whose cost is dominated by its
// std::function metric (docs/perf-log.md).
#include <cstddef>
#include <memory>
#include <vector>

namespace dmgplace::runtime {

class NearestStates {
 public:
  static constexpr std::size_t kScan = 32768;
  static constexpr std::size_t kBlock = 8;  // points per block of the scan's layout
  explicit NearestStates(std::size_t dim);
  ~NearestStates();
  NearestStates(const NearestStates&) = delete;
  NearestStates& operator=(const NearestStates&) = delete;

  // Stores q (dim values); returns its index (0, 1, ...).
  std::size_t add(const double* q);
  // Takes point i out of the search (its index stays taken; point(i) still reads it).
  void remove(std::size_t i);
  // Index of the nearest point not removed; at least one must be left.
  std::size_t nearest(const double* q) const;
  std::size_t size() const { return flat_.size() / dim_; }
  const double* point(std::size_t i) const { return flat_.data() + i * dim_; }

 private:
  struct Gnat;  // OMPL's GNAT over indices (not in this header: the installed headers name no OMPL type)
  double distance(std::size_t a, std::size_t b) const;
  std::size_t dim_;
  std::vector<double> flat_;    // one row per point
  std::vector<double> blocks_;  // the same points in blocks of kBlock, coordinate by coordinate (the scan's SIMD lanes)
  std::unique_ptr<Gnat> gnat_;
  std::vector<char> removed_;  // per index; removed points hold kEmpty in blocks_ and stay in GNAT
  std::size_t removed_count_ = 0;
  mutable const double* query_ = nullptr;  // the point GNAT's probe index stands for
};

}  // namespace dmgplace::runtime
