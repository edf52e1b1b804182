#include "dmgplace/runtime/system/simd_dispatch.hpp"

#include <atomic>

namespace dmgplace::runtime {
namespace {

bool cpu_has_avx2() {
#if defined(__x86_64__) || defined(__i386__)
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

std::atomic<int>& chosen() {
  static std::atomic<int> p{int(cpu_has_avx2() ? SimdPath::Avx2 : SimdPath::Portable)};
  return p;
}

}  // namespace

SimdPath simd_path() { return SimdPath(chosen().load(std::memory_order_relaxed)); }

void force_simd_path(SimdPath p) { chosen() = int(p == SimdPath::Avx2 && !cpu_has_avx2() ? SimdPath::Portable : p); }

const char* to_string(SimdPath p) { return p == SimdPath::Avx2 ? "avx2" : "portable"; }

}  // namespace dmgplace::runtime
