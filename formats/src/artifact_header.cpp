#include "dmgplace/formats/artifact_header.hpp"

#include <ctime>

#ifndef DMGPLACE_VERSION
#define DMGPLACE_VERSION "0.0.0"
#endif

namespace dmgplace::formats {

const char* tool_version() { return DMGPLACE_VERSION; }

std::string utc_now_iso8601() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace dmgplace::formats
