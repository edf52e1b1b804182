// check_pcd_layout: the PCD header and body size, checked before PCL reads the file.
#include "pcd_layout.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools::detail {
namespace {

// PCL turns an unreadable ascii value into NaN, which would then vanish as a "hole": every value
// must be a number (nan and inf included) and every point line complete.
void check_ascii_body(const std::string& file, std::ifstream& in, std::size_t offset, std::size_t points,
                      std::size_t values_per_point) {
  in.clear();
  in.seekg(std::streamoff(offset));
  std::string line, token;
  std::size_t row = 0;
  while (row < points && std::getline(in, line)) {
    std::istringstream ls(line);
    std::size_t n = 0;
    while (ls >> token) {
      char* end = nullptr;
      std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size())
        throw Error(file, "point " + std::to_string(row), "'" + token.substr(0, 40) + "' is not a number");
      ++n;
    }
    if (n == 0) continue;  // blank line
    if (n != values_per_point)
      throw Error(file, "point " + std::to_string(row),
                  std::to_string(n) + " values, the header says " + std::to_string(values_per_point));
    ++row;
  }
  if (row < points)
    throw Error(file, "DATA", std::to_string(row) + " point lines, the header promises " + std::to_string(points));
}

using Header = std::map<std::string, std::vector<std::string>>;

// The header's lines up to DATA, each key's values; `data_offset` where the body starts.
Header read_header(const std::string& file, std::ifstream& in, std::size_t& data_offset) {
  Header h;
  std::string line;
  while (h.find("DATA") == h.end()) {
    if (!std::getline(in, line)) throw Error(file, "header", "ends before a DATA line (not a PCD file?)");
    if (line.size() > 4096) throw Error(file, "header", "line too long (not a PCD file?)");
    std::istringstream ls(line);
    std::string key, v;
    if (!(ls >> key) || key[0] == '#') continue;
    static const char* known[] = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                  "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
    if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return key == k; }) == std::end(known))
      throw Error(file, "header", "unexpected line '" + line.substr(0, 40) + "' (not a PCD file?)");
    auto& values = h[key];
    while (ls >> v) values.push_back(v);
  }
  data_offset = std::size_t(in.tellg());
  return h;
}

// The fields' layout: values and bytes per point, and the number of points.
struct Layout {
  std::size_t values_per_point = 0, point_step = 0, points = 0;
};

Layout check_fields(const std::string& file, Header& h) {
  for (const char* key : {"FIELDS", "SIZE", "TYPE", "WIDTH", "POINTS"})
    if (h[key].empty()) throw Error(file, key, "missing from the header");
  const std::size_t nf = h["FIELDS"].size();
  if (h["COUNT"].empty()) h["COUNT"].assign(nf, "1");
  if (h["SIZE"].size() != nf || h["TYPE"].size() != nf || h["COUNT"].size() != nf)
    throw Error(file, "FIELDS", "FIELDS, SIZE, TYPE and COUNT list different numbers of entries");
  auto count = [&](const std::string& key, const std::string& text) {
    std::size_t pos = 0;
    unsigned long long v = 0;
    try {
      v = std::stoull(text, &pos);
    } catch (const std::exception&) {
      pos = 0;
    }
    if (pos != text.size() || text[0] == '-' || v > (1ull << 31))
      throw Error(file, key, "'" + text + "' is not a count");
    return std::size_t(v);
  };
  Layout l;
  for (std::size_t i = 0; i < nf; ++i) {
    const std::size_t size = count("SIZE", h["SIZE"][i]);
    if (size != 1 && size != 2 && size != 4 && size != 8) throw Error(file, "SIZE", "field size must be 1, 2, 4 or 8");
    if (h["TYPE"][i] != "F" && h["TYPE"][i] != "I" && h["TYPE"][i] != "U")
      throw Error(file, "TYPE", "field type must be F, I or U");
    l.values_per_point += count("COUNT", h["COUNT"][i]);
    l.point_step += size * count("COUNT", h["COUNT"][i]);
  }
  const std::size_t width = count("WIDTH", h["WIDTH"][0]);
  const std::size_t height = h["HEIGHT"].empty() ? 1 : count("HEIGHT", h["HEIGHT"][0]);
  l.points = count("POINTS", h["POINTS"][0]);
  if (width * height != l.points)
    throw Error(file, "POINTS",
                std::to_string(l.points) + " points but WIDTH x HEIGHT is " + std::to_string(width * height));
  if (l.points == 0) throw Error(file, "POINTS", "the cloud is empty");
  return l;
}

// A binary_compressed body's two sizes against the header and the file.
void check_compressed_body(const std::string& file, std::ifstream& in, std::size_t offset, std::size_t body,
                           std::size_t bytes) {
  std::uint32_t sizes[2] = {0, 0};  // compressed, uncompressed
  in.seekg(std::streamoff(offset));
  if (body < 8 || !in.read(reinterpret_cast<char*>(sizes), 8))
    throw Error(file, "DATA", "binary_compressed body too short");
  if (sizes[0] == 0 || sizes[0] > body - 8 || sizes[1] != bytes)
    throw Error(file, "DATA", "binary_compressed sizes disagree with the header or the file (truncated?)");
  // LZF turns 3 bytes into at most 264: a larger claimed ratio is a lie, and PCL would allocate
  // the claimed size first (gigabytes for an 18-byte body).
  if (std::uint64_t(sizes[1]) > std::uint64_t(sizes[0]) * 88 + 264)
    throw Error(file, "DATA",
                "binary_compressed claims " + std::to_string(sizes[1]) + " bytes from " + std::to_string(sizes[0]) +
                    " compressed (LZF expands at most 88:1; corrupt)");
}

}  // namespace

// PCL trusts the header and crashes on some broken files (garbage, lying binary_compressed
// sizes), so the header and the size of the body are checked here before PCL sees the file.
void check_pcd_layout(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file, "", "cannot open file");
  std::size_t data_offset = 0;
  Header h = read_header(file, in, data_offset);
  const Layout l = check_fields(file, h);
  // PCL allocates POINTS x point size before reading: that product must not wrap around (COUNT
  // and POINTS may each be 2^31, so it can exceed 64 bits and then pass the size checks below).
  std::size_t bytes = 0;
  if (__builtin_mul_overflow(l.points, l.point_step, &bytes))
    throw Error(file, "POINTS", "POINTS x point size overflows (corrupt header)");

  const std::string data = h["DATA"].empty() ? std::string() : h["DATA"][0];
  in.seekg(0, std::ios::end);
  const std::size_t body = std::size_t(in.tellg()) - data_offset;
  if (data == "binary") {
    if (body < bytes)
      throw Error(file, "DATA",
                  "binary body holds " + std::to_string(body) + " bytes, the header promises " + std::to_string(bytes));
  } else if (data == "binary_compressed") {
    check_compressed_body(file, in, data_offset, body, bytes);
  } else if (data == "ascii") {
    check_ascii_body(file, in, data_offset, l.points, l.values_per_point);
  } else {
    throw Error(file, "DATA", "'" + data + "' is not ascii, binary or binary_compressed");
  }
}

}  // namespace dmgplace::tools::detail
