#include "h5_file_image.hpp"

#include <algorithm>

namespace dmgplace::formats::detail {

std::uint32_t lookup3(const std::uint8_t* k, std::size_t length) {
  auto rot = [](std::uint32_t x, int r) { return (x << r) ^ (x >> (32 - r)); };
  std::uint32_t a, b, c;
  a = b = c = 0xdeadbeef + std::uint32_t(length);
  auto word = [&](std::size_t i, std::size_t n) {
    std::uint32_t w = 0;
    for (std::size_t j = 0; j < n; ++j) w |= std::uint32_t(k[i + j]) << (8 * j);
    return w;
  };
  while (length > 12) {
    a += word(0, 4), b += word(4, 4), c += word(8, 4);
    a -= c, a ^= rot(c, 4), c += b, b -= a, b ^= rot(a, 6), a += c, c -= b, c ^= rot(b, 8), b += a;
    a -= c, a ^= rot(c, 16), c += b, b -= a, b ^= rot(a, 19), a += c, c -= b, c ^= rot(b, 4), b += a;
    length -= 12, k += 12;
  }
  if (length == 0) return c;
  a += word(0, std::min<std::size_t>(length, 4));
  if (length > 4) b += word(4, std::min<std::size_t>(length - 4, 4));
  if (length > 8) c += word(8, length - 8);
  c ^= b, c -= rot(b, 14), a ^= c, a -= rot(c, 11), b ^= a, b -= rot(a, 25), c ^= b, c -= rot(b, 16);
  a ^= c, a -= rot(c, 4), b ^= a, b -= rot(a, 14), c ^= b, c -= rot(b, 24);
  return c;
}

void fix_superblock_checksum(std::vector<char>& image) {
  auto* u = reinterpret_cast<std::uint8_t*>(image.data());
  if (image.size() < 12 || u[8] < 2) return;          // versions 0 and 1 have no checksum
  const std::size_t at = 12 + 4 * std::size_t(u[9]);  // four addresses of sizeof_addr bytes
  if (image.size() < at + 4) return;
  const std::uint32_t sum = lookup3(u, at);
  for (int i = 0; i < 4; ++i) u[at + std::size_t(i)] = std::uint8_t(sum >> (8 * i));
}

}  // namespace dmgplace::formats::detail
