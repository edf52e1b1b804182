#include "dmgplace/formats/h5_reader.hpp"

#include <algorithm>

#include "dmgplace/formats/sha256.hpp"
#include "h5_common.hpp"

namespace dmgplace::formats {
namespace fs = std::filesystem;
using detail::check;
using detail::check_status;
using detail::Handle;

namespace {
std::string shape_text(const std::vector<std::size_t>& d) {
  std::string s = "(";
  for (std::size_t i = 0; i < d.size(); ++i) s += (i ? "," : "") + std::to_string(d[i]);
  return s + ")";
}
std::string shape_text(const std::vector<long>& d) {
  std::string s = "(";
  for (std::size_t i = 0; i < d.size(); ++i) s += (i ? "," : "") + (d[i] < 0 ? std::string("*") : std::to_string(d[i]));
  return s + ")";
}
}  // namespace

H5Reader::H5Reader(const fs::path& path) : file_name_(path.string()) {
  detail::quiet_hdf5();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(file_name_, "", "no such file");
  if (!fs::is_regular_file(path, ec)) throw Error(file_name_, "", "not a regular file");
  file_size_ = fs::file_size(path, ec);
  if (ec || file_size_ == 0) throw Error(file_name_, "", "empty file");
  htri_t is_h5 = H5Fis_hdf5(path.c_str());
  if (is_h5 <= 0) throw Error(file_name_, "", "not an HDF5 file (no valid HDF5 signature; corrupt or wrong file)");
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) throw Error(file_name_, "", "cannot open as HDF5 (corrupt? " + detail::hdf5_error_text() + ")");
  file_ = f;
  try {
    if (H5Aexists(file_, "schema") <= 0) throw Error(file_name_, "", "no 'schema' attribute: not a dmgplace artifact");
    header_.schema = detail::read_string_attribute(file_, "schema", file_name_);
    {
      if (H5Aexists(file_, "schema_version") <= 0) throw Error(file_name_, "", "no 'schema_version' attribute");
      Handle attr =
          check(H5Aopen(file_, "schema_version", H5P_DEFAULT), H5Aclose, file_name_, "schema_version", "cannot open");
      int v = 0;
      check_status(H5Aread(attr.get(), H5T_NATIVE_INT, &v), file_name_, "schema_version", "cannot read");
      header_.schema_version = v;
    }
    auto opt = [&](const char* n) {
      return H5Aexists(file_, n) > 0 ? detail::read_string_attribute(file_, n, file_name_) : std::string();
    };
    header_.tool_version = opt("tool_version");
    header_.created_utc = opt("created_utc");
    header_.parameters_json = opt("parameters");
    if (H5Lexists(file_, "inputs", H5P_DEFAULT) > 0) {
      Handle g = check(H5Gopen2(file_, "inputs", H5P_DEFAULT), H5Gclose, file_name_, "inputs", "cannot open");
      H5O_info_t info;
      check_status(H5Oget_info2(g.get(), &info, H5O_INFO_NUM_ATTRS), file_name_, "inputs", "cannot inspect");
      if (info.num_attrs > 100000) throw Error(file_name_, "inputs", "implausible attribute count (corrupt)");
      for (hsize_t i = 0; i < info.num_attrs; ++i) {
        char name[256] = {0};
        if (H5Aget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT) < 0)
          throw Error(file_name_, "inputs", "cannot read attribute name");
        std::string line = detail::read_string_attribute(g.get(), name, file_name_);
        auto sep = line.find("  ");
        if (sep != 64) throw Error(file_name_, std::string("inputs/") + name, "malformed input record");
        header_.inputs.push_back({line.substr(sep + 2), line.substr(0, 64)});
      }
    }
  } catch (...) {
    H5Fclose(file_);
    file_ = -1;
    throw;
  }
}

H5Reader::~H5Reader() {
  if (file_ >= 0) H5Fclose(file_);
}

void H5Reader::require_schema(const std::string& schema, int version) const {
  if (header_.schema != schema)
    throw Error(file_name_, "schema", "is '" + header_.schema + "', expected '" + schema + "'");
  if (header_.schema_version != version)
    throw Error(file_name_, "schema_version",
                "is " + std::to_string(header_.schema_version) + ", this build reads version " +
                    std::to_string(version) + " (re-bake the artifact with this dmgplace)");
}

bool H5Reader::has(const std::string& name) const {
  // H5Lexists fails on intermediate missing groups; walk the path.
  std::string prefix;
  std::size_t pos = 0;
  while (true) {
    std::size_t next = name.find('/', pos);
    prefix = name.substr(0, next);
    if (H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (next == std::string::npos) return true;
    pos = next + 1;
  }
}

template <class T>
Array<T> H5Reader::read_typed(const std::string& name, std::vector<long> want, long mem_type, bool is_float) const {
  if (!has(name)) throw Error(file_name_, name, "missing dataset");
  Handle ds = check(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose, file_name_, name, "cannot open dataset");
  Handle type = check(H5Dget_type(ds.get()), H5Tclose, file_name_, name, "no type");
  H5T_class_t cls = H5Tget_class(type.get());
  if (is_float ? cls != H5T_FLOAT : cls != H5T_INTEGER)
    throw Error(file_name_, name,
                std::string("wrong element type (expected ") + (is_float ? "float" : "integer") + ")");
  if (H5Tget_size(type.get()) != sizeof(T)) throw Error(file_name_, name, "wrong element size");
  Handle space = check(H5Dget_space(ds.get()), H5Sclose, file_name_, name, "no dataspace");
  int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 || rank > 8) throw Error(file_name_, name, "invalid rank (corrupt)");
  hsize_t hd[8];
  H5Sget_simple_extent_dims(space.get(), hd, nullptr);
  Array<T> out;
  out.dims.assign(hd, hd + rank);
  if (rank != int(want.size()))
    throw Error(file_name_, name, "wrong shape " + shape_text(out.dims) + ", expected " + shape_text(want));
  for (int i = 0; i < rank; ++i)
    if (want[i] >= 0 && std::size_t(want[i]) != out.dims[i])
      throw Error(file_name_, name, "wrong shape " + shape_text(out.dims) + ", expected " + shape_text(want));
  std::size_t count = 1;
  for (auto d : out.dims) {
    if (d != 0 && count > (std::size_t(1) << 40) / d) throw Error(file_name_, name, "implausible size (corrupt)");
    count *= d;
  }
  // Deflate cannot expand data more than ~1032:1; anything beyond that is a corrupt header, so
  // refuse before allocating.
  if (count * sizeof(T) > std::max<std::uintmax_t>(1 << 20, file_size_ * 1100))
    throw Error(file_name_, name,
                "declared size " + std::to_string(count * sizeof(T)) + " bytes cannot fit in a file of " +
                    std::to_string(file_size_) + " bytes (corrupt)");
  out.data.resize(count);
  if (count > 0)
    check_status(H5Dread(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data.data()), file_name_, name,
                 "cannot read dataset (checksum error or corrupt file)");
  if (H5Aexists(ds.get(), "sha256") <= 0) throw Error(file_name_, name, "dataset has no sha256 digest");
  std::string digest = detail::read_string_attribute(ds.get(), "sha256", file_name_);
  if (digest != sha256_hex(out.data.data(), count * sizeof(T)))
    throw Error(file_name_, name, "content does not match its sha256 digest (corrupt file)");
  return out;
}

Array<double> H5Reader::read_f64(const std::string& n, std::vector<long> d) const {
  return read_typed<double>(n, std::move(d), H5T_NATIVE_DOUBLE, true);
}
Array<float> H5Reader::read_f32(const std::string& n, std::vector<long> d) const {
  return read_typed<float>(n, std::move(d), H5T_NATIVE_FLOAT, true);
}
Array<std::int32_t> H5Reader::read_i32(const std::string& n, std::vector<long> d) const {
  return read_typed<std::int32_t>(n, std::move(d), H5T_NATIVE_INT32, false);
}
Array<std::int64_t> H5Reader::read_i64(const std::string& n, std::vector<long> d) const {
  return read_typed<std::int64_t>(n, std::move(d), H5T_NATIVE_INT64, false);
}
Array<std::uint8_t> H5Reader::read_u8(const std::string& n, std::vector<long> d) const {
  return read_typed<std::uint8_t>(n, std::move(d), H5T_NATIVE_UINT8, false);
}

std::vector<std::string> H5Reader::read_strings(const std::string& name) const {
  auto bytes = read_u8(name, {-1});
  std::vector<std::string> out;
  auto count = attribute(name, "count");
  if (!count) throw Error(file_name_, name, "string list has no 'count' attribute");
  std::string all(bytes.data.begin(), bytes.data.end());
  std::size_t n = 0;
  try {
    n = std::stoul(*count);
  } catch (...) {
    throw Error(file_name_, name, "bad 'count' attribute");
  }
  if (n > 0) {
    std::size_t pos = 0;
    while (true) {
      auto next = all.find('\n', pos);
      out.push_back(all.substr(pos, next == std::string::npos ? std::string::npos : next - pos));
      if (next == std::string::npos) break;
      pos = next + 1;
    }
  }
  if (out.size() != n)
    throw Error(file_name_, name, "holds " + std::to_string(out.size()) + " strings, 'count' says " + *count);
  return out;
}

std::vector<std::size_t> H5Reader::shape(const std::string& name) const {
  if (!has(name)) throw Error(file_name_, name, "missing dataset");
  Handle ds = check(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose, file_name_, name, "cannot open dataset");
  Handle space = check(H5Dget_space(ds.get()), H5Sclose, file_name_, name, "no dataspace");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 || rank > 8) throw Error(file_name_, name, "invalid rank (corrupt)");
  hsize_t hd[8];
  H5Sget_simple_extent_dims(space.get(), hd, nullptr);
  return std::vector<std::size_t>(hd, hd + rank);
}

std::vector<std::string> H5Reader::read_utf8_strings(const std::string& name) const {
  const auto dims = shape(name);
  Handle ds = check(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose, file_name_, name, "cannot open dataset");
  Handle type = check(H5Dget_type(ds.get()), H5Tclose, file_name_, name, "no type");
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0 ||
      H5Tget_cset(type.get()) != H5T_CSET_UTF8)
    throw Error(file_name_, name, "wrong element type (expected fixed-length UTF-8 strings)");
  if (dims.size() != 1) throw Error(file_name_, name, "wrong shape " + shape_text(dims) + ", expected (*)");
  const std::size_t width = H5Tget_size(type.get()), count = dims[0];
  // As read_typed: deflate expands at most ~1032:1, so a larger declared size is a corrupt header.
  const std::uintmax_t limit = std::max<std::uintmax_t>(1 << 20, file_size_ * 1100);
  if (width == 0 || width > (std::size_t(1) << 20) || count > limit / width)
    throw Error(file_name_, name, "implausible size (corrupt)");
  std::vector<char> bytes(count * width);
  if (count > 0)
    check_status(H5Dread(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()), file_name_, name,
                 "cannot read dataset (checksum error or corrupt file)");
  if (H5Aexists(ds.get(), "sha256") <= 0) throw Error(file_name_, name, "dataset has no sha256 digest");
  if (detail::read_string_attribute(ds.get(), "sha256", file_name_) != sha256_hex(bytes.data(), bytes.size()))
    throw Error(file_name_, name, "content does not match its sha256 digest (corrupt file)");
  std::vector<std::string> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    const char* at = bytes.data() + i * width;
    out[i].assign(at, std::find(at, at + width, '\0'));
    if (!detail::is_valid_utf8(out[i]))
      throw Error(file_name_, name + "[" + std::to_string(i) + "]", "not valid UTF-8");
  }
  return out;
}

std::optional<std::string> H5Reader::attribute(const std::string& object, const std::string& name) const {
  if (object.empty() || object == "/") {
    if (H5Aexists(file_, name.c_str()) <= 0) return std::nullopt;
    return detail::read_string_attribute(file_, name.c_str(), file_name_);
  }
  if (!has(object)) return std::nullopt;
  Handle obj = check(H5Oopen(file_, object.c_str(), H5P_DEFAULT), H5Oclose, file_name_, object, "cannot open");
  if (H5Aexists(obj.get(), name.c_str()) <= 0) return std::nullopt;
  return detail::read_string_attribute(obj.get(), name.c_str(), file_name_);
}

std::vector<std::string> H5Reader::dataset_names() const {
  std::vector<std::string> names;
  auto cb = [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
    if (info->type == H5O_TYPE_DATASET) static_cast<std::vector<std::string>*>(data)->push_back(name);
    return static_cast<std::vector<std::string>*>(data)->size() > 1000000 ? -1 : 0;
  };
  check_status(H5Ovisit2(file_, H5_INDEX_NAME, H5_ITER_INC, cb, &names, H5O_INFO_BASIC), file_name_, "",
               "cannot list datasets (corrupt file)");
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> H5Reader::verify_all_checksums() const {
  std::vector<std::string> problems;
  std::vector<std::string> names;
  try {
    names = dataset_names();
  } catch (const Error& e) {
    return {e.what()};
  }
  for (const auto& name : names) {
    try {
      Handle ds = check(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose, file_name_, name, "cannot open");
      Handle type = check(H5Dget_type(ds.get()), H5Tclose, file_name_, name, "no type");
      Handle space = check(H5Dget_space(ds.get()), H5Sclose, file_name_, name, "no dataspace");
      int rank = H5Sget_simple_extent_ndims(space.get());
      if (rank < 0 || rank > 8) throw Error(file_name_, name, "invalid rank (corrupt)");
      std::vector<long> any(std::size_t(rank), -1);
      bool is_float = H5Tget_class(type.get()) == H5T_FLOAT;
      bool is_string = H5Tget_class(type.get()) == H5T_STRING;
      std::size_t size = H5Tget_size(type.get());
      ds.reset();
      if (is_string) read_utf8_strings(name);
      else if (is_float && size == 8) read_f64(name, any);
      else if (is_float && size == 4) read_f32(name, any);
      else if (!is_float && size == 4) read_i32(name, any);
      else if (!is_float && size == 8) read_i64(name, any);
      else if (!is_float && size == 1) read_u8(name, any);
      else throw Error(file_name_, name, "unsupported element type");
    } catch (const Error& e) {
      problems.push_back(e.what());
    }
  }
  return problems;
}

}  // namespace dmgplace::formats
