#pragma once
// Opens an artifact read-only, checks its header, and reads datasets with their shapes, types and
// checksums verified. Every failure is a dmgplace::Error naming the file and the dataset.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/h5_array.hpp"

namespace dmgplace::formats {

class H5Reader {
 public:
  explicit H5Reader(const std::filesystem::path& path);
  ~H5Reader();
  H5Reader(const H5Reader&) = delete;
  H5Reader& operator=(const H5Reader&) = delete;

  const ArtifactHeader& header() const { return header_; }
  const std::string& file() const { return file_name_; }
  // Throws unless the schema name matches and the version is one this build reads.
  void require_schema(const std::string& schema, int version) const;

  bool has(const std::string& name) const;
  // Reads a dataset; `dims` gives the expected shape with -1 for "any" (rank must match).
  Array<double> read_f64(const std::string& name, std::vector<long> dims) const;
  Array<float> read_f32(const std::string& name, std::vector<long> dims) const;
  Array<std::int32_t> read_i32(const std::string& name, std::vector<long> dims) const;
  Array<std::int64_t> read_i64(const std::string& name, std::vector<long> dims) const;
  Array<std::uint8_t> read_u8(const std::string& name, std::vector<long> dims) const;
  std::vector<std::string> read_strings(const std::string& name) const;
  // A 1-D dataset of fixed-length UTF-8 strings (H5Writer::write_utf8_strings), NUL padding removed.
  std::vector<std::string> read_utf8_strings(const std::string& name) const;
  // A dataset's shape, whatever its element type.
  std::vector<std::size_t> shape(const std::string& name) const;
  std::optional<std::string> attribute(const std::string& object, const std::string& name) const;
  // Every dataset path in the file (for validation).
  std::vector<std::string> dataset_names() const;
  // Reads every dataset once, verifying each checksum; returns one message per problem.
  std::vector<std::string> verify_all_checksums() const;

 private:
  template <class T>
  Array<T> read_typed(const std::string& name, std::vector<long> dims, long mem_type, bool is_float) const;
  std::string file_name_;
  std::uintmax_t file_size_ = 0;
  long file_ = -1;
  ArtifactHeader header_;
};

}  // namespace dmgplace::formats
