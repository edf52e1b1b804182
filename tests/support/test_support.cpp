#include "test_support.hpp"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <random>
#include <sstream>

namespace dmgplace::test {
namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  std::random_device rd;
  path_ = fs::temp_directory_path() / ("dmgplace-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) +
                                       "-" + std::to_string(rd()));
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

fs::path shared_datasets() {
  fs::path p = DMGPLACE_SHARED_DATASETS;
  std::error_code ec;
  return fs::is_directory(p, ec) ? fs::canonical(p) : fs::path();
}

fs::path source_dir() { return DMGPLACE_SOURCE_DIR; }
std::string cli_path() { return DMGPLACE_CLI; }

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string builtin_volume(const std::string& scene) {
  std::string v = read_text(source_dir() / "datasets/scenes" / (scene + ".volume"));
  v.erase(v.find_last_not_of(" \n\r\t") + 1);
  return v;
}

}  // namespace dmgplace::test
