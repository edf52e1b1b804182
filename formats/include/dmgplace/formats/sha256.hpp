#pragma once
// SHA-256 (FIPS 180-4) for input-file hashes and per-dataset digests, computed by libcrypto
// (OpenSSL, already in the process through HDF5): every artifact's datasets are hashed on every
// load, and libcrypto's SHA-NI/AVX2 code is several times faster than a portable loop.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace dmgplace::formats {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void update(const void* data, std::size_t size);
  std::array<std::uint8_t, 32> finish();
  std::string finish_hex();

 private:
  struct Context;
  std::unique_ptr<Context> ctx_;
};

std::string sha256_hex(const void* data, std::size_t size);
// Throws dmgplace::Error naming the file when it cannot be read.
std::string sha256_file(const std::filesystem::path& path);

}  // namespace dmgplace::formats
