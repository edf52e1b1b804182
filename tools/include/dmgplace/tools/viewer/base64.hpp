#pragma once
// Base64 (RFC 4648, padded): how the viewer page carries typed arrays inside its JSON.
#include <cstddef>
#include <string>
#include <vector>

namespace dmgplace::tools::viewer {

std::string base64(const void* data, std::size_t bytes);
template <class T>
std::string base64(const std::vector<T>& v) {
  return base64(v.data(), v.size() * sizeof(T));
}

}  // namespace dmgplace::tools::viewer
