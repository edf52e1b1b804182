#pragma once
// Writes one artifact atomically: everything goes to a hidden temporary file in the target's
// folder, which is renamed over the target only by commit(). Until then the old file is untouched;
// a writer destroyed without commit() removes its temporary file.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "dmgplace/formats/artifact_header.hpp"

namespace dmgplace::formats {

class H5Writer {
 public:
  H5Writer(std::filesystem::path target, const ArtifactHeader& header);
  ~H5Writer();
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  // Datasets are chunked with shuffle + deflate + Fletcher32 and carry a SHA-256 of their bytes.
  // `name` is a path such as "mesh/vertices"; groups are created as needed.
  // write_contiguous: one uncompressed block (no chunks, no filters: HDF5 reads it with one
  // copy), for large arrays read on every load; the SHA-256 still guards it.
  void write_contiguous(const std::string& name, std::span<const float> data, std::vector<std::size_t> dims);
  void write(const std::string& name, std::span<const double> data, std::vector<std::size_t> dims);
  void write(const std::string& name, std::span<const float> data, std::vector<std::size_t> dims);
  void write(const std::string& name, std::span<const std::int32_t> data, std::vector<std::size_t> dims);
  void write(const std::string& name, std::span<const std::int64_t> data, std::vector<std::size_t> dims);
  void write(const std::string& name, std::span<const std::uint8_t> data, std::vector<std::size_t> dims);
  void write_strings(const std::string& name, const std::vector<std::string>& values);
  // One HDF5 string per value: fixed-length UTF-8, NUL-padded to the longest value (h5py reads a
  // numpy bytes array). Filtered like write(); the sha256 covers the stored, padded bytes. Values
  // must be valid UTF-8 without NUL bytes (padding would eat a trailing one).
  void write_utf8_strings(const std::string& name, const std::vector<std::string>& values);
  // A group whose members list in creation order (h5py and pandas show columns as written).
  void ordered_group(const std::string& name);
  // A string attribute on the root ("" ) or on an existing group/dataset.
  void attribute(const std::string& object, const std::string& name, const std::string& value);

  // Flushes, fsyncs and renames into place. Throws dmgplace::Error (temp file removed) on failure.
  void commit();
  const std::filesystem::path& temp_path() const { return temp_; }

 private:
  void write_raw(const std::string& name, const void* data, long type, std::size_t elem_size,
                 std::vector<std::size_t> dims, bool chunked = true);
  void discard() noexcept;
  std::filesystem::path target_, temp_;
  long file_ = -1;  // hid_t, kept opaque so HDF5 headers stay out of ours
  bool committed_ = false;
};

}  // namespace dmgplace::formats
