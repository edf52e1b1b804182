#include "dmgplace/tools/viewer/base64.hpp"

#include <cstdint>

namespace dmgplace::tools::viewer {

std::string base64(const void* data, std::size_t bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const std::uint8_t*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes; i += 3) {
    const std::size_t n = bytes - i < 3 ? bytes - i : 3;
    std::uint32_t v = std::uint32_t(p[i]) << 16;
    if (n > 1) v |= std::uint32_t(p[i + 1]) << 8;
    if (n > 2) v |= p[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += n > 1 ? kAlphabet[(v >> 6) & 63] : '=';
    out += n > 2 ? kAlphabet[v & 63] : '=';
  }
  return out;
}

}  // namespace dmgplace::tools::viewer
