#include "dmgplace/formats/h5_writer.hpp"

#include "dmgplace/formats/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "dmgplace/formats/sha256.hpp"
#include "h5_common.hpp"
#include "h5_file_image.hpp"

namespace dmgplace::formats {
namespace fs = std::filesystem;
using detail::check;
using detail::check_status;
using detail::Handle;

namespace {
// The whole file image into `p` (the writer's empty temporary file), then fsync. Every failing call is
// reported: write(2), fsync(2) and close(2) are where a full disk shows (ENOSPC, EFBIG, EDQUOT).
void write_image(const fs::path& p, const std::vector<char>& image, const std::string& file) {
  const int fd = ::open(p.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) throw Error(file, "", "cannot open temporary file " + p.string() + ": " + std::strerror(errno));
  auto fail = [&](const char* what) {
    const int err = errno;
    ::close(fd);
    throw Error(file, "", std::string(what) + " (disk full?): " + std::strerror(err));
  };
  for (std::size_t done = 0; done < image.size();) {
    const ssize_t n = ::write(fd, image.data() + done, image.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write failed");
    done += std::size_t(n);
  }
  if (::fsync(fd) != 0) fail("fsync failed");
  if (::close(fd) != 0) throw Error(file, "", std::string("close failed (disk full?): ") + std::strerror(errno));
}
}  // namespace

H5Writer::H5Writer(fs::path target, const ArtifactHeader& header) : target_(std::move(target)) {
  detail::quiet_hdf5();
  if (target_.filename().empty()) throw Error(target_.string(), "", "output path names no file");
  fs::path parent = target_.parent_path().empty() ? fs::path(".") : target_.parent_path();
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) throw Error(target_.string(), "", "output folder does not exist");
  temp_ = temporary_name_for(target_.parent_path().empty() ? fs::path(".") / target_ : target_);
  remove_stale_temporaries(target_);
  Handle fapl = Handle(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  // The 1.10 format checksums superblock, object headers and B-trees: metadata corruption is caught.
  H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V110, H5F_LIBVER_LATEST);
  // Built in memory (core driver, no backing store) and written by commit() with plain write(2):
  // HDF5 itself never meets a full disk. It loses write errors of cached chunks on H5Dclose, and a
  // failed H5Fclose leaves a dangling file that crashes the process at exit (HDF5 1.10.8).
  H5Pset_fapl_core(fapl.get(), 8 << 20, 0);  // grows 8 MiB at a time (glibc remaps large blocks)
  // The empty temporary file already marks this writer's target (kill -9: removed by the next).
  const int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    throw Error(target_.string(), "", "cannot create temporary file " + temp_.string() + ": " + std::strerror(errno));
  ::close(fd);
  hid_t f = H5Fcreate(temp_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (f < 0) {
    discard();
    throw Error(target_.string(), "", "cannot create the artifact in memory (" + detail::hdf5_error_text() + ")");
  }
  file_ = f;
  try {
    attribute("", "schema", header.schema);
    {
      Handle space = Handle(H5Screate(H5S_SCALAR), H5Sclose);
      Handle attr = check(H5Acreate2(file_, "schema_version", H5T_STD_I32LE, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                          H5Aclose, target_.string(), "attribute schema_version", "cannot create");
      int v = header.schema_version;
      check_status(H5Awrite(attr.get(), H5T_NATIVE_INT, &v), target_.string(), "schema_version", "cannot write");
    }
    attribute("", "tool_version", header.tool_version.empty() ? tool_version() : header.tool_version);
    attribute("", "created_utc", header.created_utc.empty() ? utc_now_iso8601() : header.created_utc);
    attribute("", "parameters", header.parameters_json.empty() ? "{}" : header.parameters_json);
    Handle inputs = check(H5Gcreate2(file_, "inputs", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                          target_.string(), "group inputs", "cannot create");
    for (std::size_t i = 0; i < header.inputs.size(); ++i) {
      char key[32];
      std::snprintf(key, sizeof key, "%03zu", i);
      // "sha256  path", the format sha256sum prints, so a user can check inputs by hand.
      detail::write_string_attribute(inputs.get(), key, header.inputs[i].sha256 + "  " + header.inputs[i].path,
                                     target_.string());
    }
  } catch (...) {
    discard();
    throw;
  }
}

H5Writer::~H5Writer() {
  if (!committed_) discard();
}

void H5Writer::discard() noexcept {
  if (file_ >= 0) H5Fclose(file_);
  file_ = -1;
  std::error_code ec;
  if (!temp_.empty()) fs::remove(temp_, ec);
}

void H5Writer::write_raw(const std::string& name, const void* data, long type, std::size_t elem_size,
                         std::vector<std::size_t> dims, bool chunked) {
  const std::string file = target_.string();
  if (file_ < 0) throw Error(file, name, "writer already closed");
  if (dims.empty()) throw Error(file, name, "dataset needs at least one dimension");
  std::vector<hsize_t> hd(dims.begin(), dims.end());
  std::size_t count = 1;
  for (auto d : dims) count *= d;
  Handle space = check(H5Screate_simple(int(hd.size()), hd.data(), nullptr), H5Sclose, file, name, "bad shape");
  Handle lcpl = Handle(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  Handle dcpl = Handle(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (count > 0 && chunked) {
    // Chunks of about 256 KiB along the first dimension.
    std::vector<hsize_t> chunk = hd;
    std::size_t row_bytes = elem_size;
    for (std::size_t i = 1; i < hd.size(); ++i) row_bytes *= hd[i];
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(hd[0], (256 * 1024) / std::max<std::size_t>(1, row_bytes)));
    H5Pset_chunk(dcpl.get(), int(chunk.size()), chunk.data());
    H5Pset_fletcher32(dcpl.get());
    H5Pset_shuffle(dcpl.get());
    H5Pset_deflate(dcpl.get(), 4);
  }
  Handle ds = check(H5Dcreate2(file_, name.c_str(), type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT), H5Dclose,
                    file, name, "cannot create dataset");
  if (count > 0)
    check_status(H5Dwrite(ds.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), file, name, "cannot write dataset");
  detail::write_string_attribute(ds.get(), "sha256", sha256_hex(data, count * elem_size), file);
}

void H5Writer::write_contiguous(const std::string& n, std::span<const float> d, std::vector<std::size_t> dims) {
  write_raw(n, d.data(), H5T_NATIVE_FLOAT, sizeof(float), std::move(dims), false);
}
void H5Writer::write(const std::string& n, std::span<const double> d, std::vector<std::size_t> dims) {
  write_raw(n, d.data(), H5T_NATIVE_DOUBLE, sizeof(double), std::move(dims));
}
void H5Writer::write(const std::string& n, std::span<const float> d, std::vector<std::size_t> dims) {
  write_raw(n, d.data(), H5T_NATIVE_FLOAT, sizeof(float), std::move(dims));
}
void H5Writer::write(const std::string& n, std::span<const std::int32_t> d, std::vector<std::size_t> dims) {
  write_raw(n, d.data(), H5T_NATIVE_INT32, sizeof(std::int32_t), std::move(dims));
}
void H5Writer::write(const std::string& n, std::span<const std::int64_t> d, std::vector<std::size_t> dims) {
  write_raw(n, d.data(), H5T_NATIVE_INT64, sizeof(std::int64_t), std::move(dims));
}
void H5Writer::write(const std::string& n, std::span<const std::uint8_t> d, std::vector<std::size_t> dims) {
  write_raw(n, d.data(), H5T_NATIVE_UINT8, sizeof(std::uint8_t), std::move(dims));
}

void H5Writer::write_strings(const std::string& name, const std::vector<std::string>& values) {
  // Stored as one '\n'-joined byte array: simple, checksummed, and no variable-length heap to corrupt.
  std::string joined;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i].find('\n') != std::string::npos) throw Error(target_.string(), name, "string contains a newline");
    joined += values[i];
    if (i + 1 < values.size()) joined += '\n';
  }
  std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(joined.data()), joined.size());
  write(name, bytes, {joined.size()});
  Handle ds = Handle(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose);
  detail::write_string_attribute(ds.get(), "count", std::to_string(values.size()), target_.string());
}

void H5Writer::write_utf8_strings(const std::string& name, const std::vector<std::string>& values) {
  std::size_t width = 1;  // HDF5 has no zero-length string type
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::string where = name + "[" + std::to_string(i) + "]";
    if (values[i].find('\0') != std::string::npos) throw Error(target_.string(), where, "string contains a NUL byte");
    if (!detail::is_valid_utf8(values[i])) throw Error(target_.string(), where, "string is not valid UTF-8");
    width = std::max(width, values[i].size());
  }
  std::vector<char> padded(values.size() * width, '\0');
  for (std::size_t i = 0; i < values.size(); ++i)
    std::copy(values[i].begin(), values[i].end(), padded.begin() + i * width);
  Handle type = check(H5Tcopy(H5T_C_S1), H5Tclose, target_.string(), name, "cannot make the string type");
  check_status(H5Tset_size(type.get(), width), target_.string(), name, "cannot size the string type");
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  write_raw(name, padded.data(), type.get(), width, {values.size()});
}

void H5Writer::ordered_group(const std::string& name) {
  const std::string file = target_.string();
  if (file_ < 0) throw Error(file, name, "writer already closed");
  Handle gcpl = Handle(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  check_status(H5Pset_link_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED), file, name,
               "cannot track creation order");
  Handle lcpl = Handle(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  check(H5Gcreate2(file_, name.c_str(), lcpl.get(), gcpl.get(), H5P_DEFAULT), H5Gclose, file, name,
        "cannot create group");
}

void H5Writer::attribute(const std::string& object, const std::string& name, const std::string& value) {
  if (file_ < 0) throw Error(target_.string(), name, "writer already closed");
  if (object.empty() || object == "/") {
    detail::write_string_attribute(file_, name, value, target_.string());
    return;
  }
  Handle obj = check(H5Oopen(file_, object.c_str(), H5P_DEFAULT), H5Oclose, target_.string(), object,
                     "no such object for attribute " + name);
  detail::write_string_attribute(obj.get(), name, value, target_.string());
}

void H5Writer::commit() {
  const std::string file = target_.string();
  if (committed_) return;
  try {
    check_status(H5Fflush(file_, H5F_SCOPE_GLOBAL), file, "", "flush failed");
    const ssize_t size = H5Fget_file_image(file_, nullptr, 0);
    if (size <= 0) throw Error(file, "", "cannot get the file image (" + detail::hdf5_error_text() + ")");
    std::vector<char> image(std::size_t(size), '\0');
    if (H5Fget_file_image(file_, image.data(), image.size()) != size)
      throw Error(file, "", "cannot get the file image (" + detail::hdf5_error_text() + ")");
    herr_t rc = H5Fclose(file_);
    file_ = -1;
    check_status(rc, file, "", "close failed");
    detail::fix_superblock_checksum(image);
    write_image(temp_, image, file);
    std::error_code ec;
    fs::rename(temp_, target_, ec);
    if (ec) throw Error(file, "", "cannot rename temporary file into place: " + ec.message());
    sync_directory(target_.parent_path());
    committed_ = true;
  } catch (...) {
    discard();
    throw;
  }
}

}  // namespace dmgplace::formats
