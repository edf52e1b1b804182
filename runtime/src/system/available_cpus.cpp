#include "dmgplace/runtime/system/available_cpus.hpp"

#include <sched.h>

#include <algorithm>
#include <thread>

namespace dmgplace::runtime {

int available_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, int(std::thread::hardware_concurrency()));  // no mask to read: the machine's
}

}  // namespace dmgplace::runtime
