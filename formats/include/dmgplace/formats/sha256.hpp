#pragma once
// SHA-256 (FIPS 180-4) for input-file hashes and per-dataset digests; no crypto library needed.
#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace dmgplace::formats {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  std::array<std::uint8_t, 32> finish();
  std::string finish_hex();

 private:
  void block(const std::uint8_t* p);
  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buf_{};
  std::size_t buf_len_ = 0;
  std::uint64_t total_ = 0;
};

std::string sha256_hex(const void* data, std::size_t size);
// Throws dmgplace::Error naming the file when it cannot be read.
std::string sha256_file(const std::filesystem::path& path);

}  // namespace dmgplace::formats
