#pragma once
// Runs fn(i) for i in [0, n) on `threads` std::threads (<= 0: every CPU the process may use), handing out indices
// one at a time so uneven work balances; the first exception is rethrown.
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "dmgplace/runtime/system/available_cpus.hpp"

namespace dmgplace::tools::detail {

template <class Fn>
void parallel_for(std::size_t n, int threads, Fn&& fn) {
  std::size_t t = threads > 0 ? std::size_t(threads) : std::size_t(runtime::available_cpus());
  t = std::min(t, n);
  if (t <= 1) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    try {
      for (std::size_t i; (i = next.fetch_add(1)) < n;) fn(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      next = n;
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t k = 1; k < t; ++k) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace dmgplace::tools::detail
