#pragma once
// Shared by the libFuzzer targets: the fuzzed bytes as a file (our readers take paths) in a
// per-process scratch folder under $TMPDIR, removed when the process exits normally.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace dmgplace::fuzz {

inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("dmgplace_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  // Registered after `dir` is complete, so it runs before dir's destructor (exit handlers run in
  // reverse order); registered inside dir's initializer it ran after and removed nothing.
  [[maybe_unused]] static const bool cleanup = std::atexit([] {
                                                 std::error_code ec;
                                                 std::filesystem::remove_all(dir, ec);
                                               }) == 0;
  return dir;
}

// Writes data[0, size) to scratch_dir()/name (replacing it) and returns the path.
inline std::filesystem::path write_input(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const auto path = scratch_dir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) std::abort();  // the harness itself failed: not a finding in the reader
  return path;
}

}  // namespace dmgplace::fuzz
