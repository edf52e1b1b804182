#pragma once
// Progress of long offline work (distance fields, DMG angles, self-distance tables), reported to
// a caller's callback: the libraries print nothing themselves. `ProgressFn(stage, done, total)`
// may be called from worker threads, serialised and throttled by ProgressReporter.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>

namespace dmgplace::tools {

using ProgressFn = std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

class ProgressReporter {
 public:
  ProgressReporter(ProgressFn f, std::string stage) : f_(std::move(f)), stage_(std::move(stage)) {}
  void add_total(std::size_t n) { total_ += n; }
  // n more units done; reports at most every 200 ms, and always the last unit.
  void done(std::size_t n = 1) {
    const std::size_t d = done_ += n;
    if (!f_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (d < total_ && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    f_(stage_, d, total_);
  }

 private:
  ProgressFn f_;
  std::string stage_;
  std::atomic<std::size_t> done_{0}, total_{0};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace dmgplace::tools
