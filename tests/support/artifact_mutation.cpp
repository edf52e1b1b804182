#include "artifact_mutation.hpp"

#include <hdf5.h>

#include <stdexcept>
#include <vector>

#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/sha256.hpp"

namespace dmgplace::test {
namespace fs = std::filesystem;
namespace {

// Minimal RAII for the HDF5 ids used here.
struct Id {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Id() {
    if (id >= 0) close(id);
  }
};

void require(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error("artifact_mutation: " + what);
}

std::size_t element_count(hid_t dataset) {
  Id space{H5Dget_space(dataset), H5Sclose};
  const hssize_t n = H5Sget_simple_extent_npoints(space.id);
  require(n >= 0, "no dataspace");
  return std::size_t(n);
}

}  // namespace

std::size_t dataset_size(const fs::path& file, const std::string& name) {
  Id f{H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  require(f.id >= 0, "cannot open " + file.string());
  Id d{H5Dopen2(f.id, name.c_str(), H5P_DEFAULT), H5Dclose};
  require(d.id >= 0, "no dataset " + name);
  return element_count(d.id);
}

double dataset_value(const fs::path& file, const std::string& name, std::size_t index) {
  Id f{H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  require(f.id >= 0, "cannot open " + file.string());
  Id d{H5Dopen2(f.id, name.c_str(), H5P_DEFAULT), H5Dclose};
  require(d.id >= 0, "no dataset " + name);
  std::vector<double> values(element_count(d.id));
  require(index < values.size(), "index out of range");
  require(H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0, "cannot read " + name);
  return values[index];
}

void mutate_dataset(const fs::path& from, const fs::path& to, const std::string& name, std::size_t index,
                    double value) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  Id f{H5Fopen(to.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose};
  require(f.id >= 0, "cannot open " + to.string());
  Id d{H5Dopen2(f.id, name.c_str(), H5P_DEFAULT), H5Dclose};
  require(d.id >= 0, "no dataset " + name);
  const std::size_t n = element_count(d.id);
  require(index < n, "index " + std::to_string(index) + " outside " + name);
  std::vector<double> values(n);
  require(H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0, "cannot read " + name);
  values[index] = value;
  // HDF5 converts double to the stored type (clipping integers; NaN becomes 0 there).
  require(H5Dwrite(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0, "cannot write " + name);
  // The digest is over the bytes the reader sees: the stored type in native layout.
  Id file_type{H5Dget_type(d.id), H5Tclose};
  Id native{H5Tget_native_type(file_type.id, H5T_DIR_ASCEND), H5Tclose};
  const std::size_t size = H5Tget_size(native.id);
  std::vector<unsigned char> bytes(n * size);
  require(H5Dread(d.id, native.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()) >= 0, "cannot re-read " + name);
  const std::string digest = formats::sha256_hex(bytes.data(), bytes.size());
  Id attr{H5Aopen(d.id, "sha256", H5P_DEFAULT), H5Aclose};
  require(attr.id >= 0, name + " has no sha256 attribute");
  Id attr_type{H5Aget_type(attr.id), H5Tclose};
  require(H5Tget_size(attr_type.id) == digest.size(), "unexpected sha256 attribute size");
  require(H5Awrite(attr.id, attr_type.id, digest.data()) >= 0, "cannot write the sha256 attribute");
}

std::vector<std::string> artifact_datasets(const fs::path& file) { return formats::H5Reader(file).dataset_names(); }

}  // namespace dmgplace::test
