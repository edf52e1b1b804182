#pragma once
// HDF5 plumbing shared by the reader and writer (private to dmgplace_formats).
#include <hdf5.h>

#include <string>
#include <string_view>
#include <type_traits>

#include "dmgplace/formats/error.hpp"

static_assert(std::is_same_v<hid_t, long> || sizeof(hid_t) == sizeof(long), "hid_t must fit in long");

namespace dmgplace::formats::detail {

// Silences HDF5's own stderr printing once; we turn its errors into exceptions.
void quiet_hdf5();
// The innermost message on HDF5's error stack, or "" when there is none.
std::string hdf5_error_text();

// RAII for any hid_t with its matching close function.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      close_ = o.close_;
      o.id_ = -1;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void reset() {
    if (id_ >= 0 && close_) close_(id_);
    id_ = -1;
  }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

inline Handle check(hid_t id, herr_t (*close)(hid_t), const std::string& file, const std::string& element,
                    const std::string& what) {
  if (id < 0) {
    std::string detail = hdf5_error_text();
    throw Error(file, element, what + (detail.empty() ? "" : " (" + detail + ")"));
  }
  return Handle(id, close);
}

inline void check_status(herr_t status, const std::string& file, const std::string& element, const std::string& what) {
  if (status < 0) {
    std::string detail = hdf5_error_text();
    throw Error(file, element, what + (detail.empty() ? "" : " (" + detail + ")"));
  }
}

// Well-formed UTF-8 (no overlong forms, surrogates or code points beyond U+10FFFF).
bool is_valid_utf8(std::string_view s);

std::string read_string_attribute(hid_t object, const char* name, const std::string& file);
void write_string_attribute(hid_t object, const std::string& name, const std::string& value, const std::string& file);

}  // namespace dmgplace::formats::detail
