#include "h5_common.hpp"

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <vector>

namespace dmgplace::formats::detail {

void quiet_hdf5() {
  static std::once_flag once;
  std::call_once(once, [] {
    H5open();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  });
}

std::string hdf5_error_text() {
  std::string text;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* err, void* data) -> herr_t {
        auto* out = static_cast<std::string*>(data);
        if (n == 0 && err->desc) *out = err->desc;  // innermost: the actual cause
        return 0;
      },
      &text);
  H5Eclear2(H5E_DEFAULT);
  return text;
}

bool is_valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    const int extra = c < 0x80 ? 0 : (c & 0xE0) == 0xC0 ? 1 : (c & 0xF0) == 0xE0 ? 2 : (c & 0xF8) == 0xF0 ? 3 : -1;
    if (extra < 0 || s.size() - i <= std::size_t(extra)) return false;  // a truncated sequence
    std::uint32_t cp = extra == 0 ? c : c & (0x3F >> extra);
    for (int k = 1; k <= extra; ++k) {
      const auto b = static_cast<unsigned char>(s[i + std::size_t(k)]);
      if ((b & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (b & 0x3F);
    }
    // The shortest encoding only; no UTF-16 surrogates; nothing beyond Unicode's range.
    const std::uint32_t least[] = {0, 0x80, 0x800, 0x10000};
    if (cp < least[extra] || (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return false;
    i += std::size_t(extra) + 1;
  }
  return true;
}

std::string read_string_attribute(hid_t object, const char* name, const std::string& file) {
  Handle attr =
      check(H5Aopen(object, name, H5P_DEFAULT), H5Aclose, file, std::string("attribute ") + name, "cannot open");
  Handle type = check(H5Aget_type(attr.get()), H5Tclose, file, std::string("attribute ") + name, "no type");
  if (H5Tget_class(type.get()) != H5T_STRING) throw Error(file, std::string("attribute ") + name, "not a string");
  if (H5Tis_variable_str(type.get()) > 0)
    throw Error(file, std::string("attribute ") + name, "variable-length string (not written by dmgplace)");
  std::size_t size = H5Tget_size(type.get());
  if (size > (std::size_t(1) << 26)) throw Error(file, std::string("attribute ") + name, "implausibly large");
  std::vector<char> buf(size + 1, '\0');
  check_status(H5Aread(attr.get(), type.get(), buf.data()), file, std::string("attribute ") + name, "cannot read");
  return std::string(buf.data());
}

void write_string_attribute(hid_t object, const std::string& name, const std::string& value, const std::string& file) {
  // Fixed-length strings live inside the (checksummed) object header; variable-length ones would
  // live in the global heap, which has no checksum and crashes HDF5 when corrupt.
  Handle type = check(H5Tcopy(H5T_C_S1), H5Tclose, file, "attribute " + name, "type");
  H5Tset_size(type.get(), std::max<std::size_t>(1, value.size()));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  Handle space = check(H5Screate(H5S_SCALAR), H5Sclose, file, "attribute " + name, "space");
  if (H5Aexists(object, name.c_str()) > 0) H5Adelete(object, name.c_str());
  Handle attr = check(H5Acreate2(object, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                      file, "attribute " + name, "cannot create");
  std::string padded = value.empty() ? std::string(1, '\0') : value;
  check_status(H5Awrite(attr.get(), type.get(), padded.data()), file, "attribute " + name, "cannot write");
}

}  // namespace dmgplace::formats::detail
