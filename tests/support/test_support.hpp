#pragma once
// Helpers every test program shares: scratch folders and the location of shared data.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::test {

// A fresh empty folder under the build's temp area, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// ../shared/datasets, or "" when it is not beside the checkout.
std::filesystem::path shared_datasets();
std::filesystem::path source_dir();
std::string cli_path();
void write_text(const std::filesystem::path& p, const std::string& text);
std::string read_text(const std::filesystem::path& p);
// The target volume of a built-in scene (datasets/scenes/SCENE.volume), as `bake-env --volume` takes it.
std::string builtin_volume(const std::string& scene);
// Running dmgplace or another program (argument vectors, no shell): run_cli.hpp.

// An axis-aligned box primitive of full extents `size` centered at `at`.
inline Shape box_shape(const Eigen::Vector3d& size, const Eigen::Vector3d& at) {
  Shape s;
  s.type = ShapeType::Box;
  s.size = size;
  s.origin.translation() = at;
  return s;
}

// Runs a test suite's shared set-up and ends the test program when it failed. GoogleTest would
// report the suite's tests as skipped, which ctest counts as passing.
template <class F>
void set_up_suite_or_exit(const char* suite, F&& set_up) {
  set_up();
  if (::testing::Test::HasFatalFailure() || ::testing::Test::HasNonfatalFailure()) {
    std::fprintf(stderr, "%s: the suite's set-up failed, see above\n", suite);
    std::fflush(nullptr);
    std::_Exit(1);
  }
}

// The message of the dmgplace::Error that f() throws, or a marker when it throws none.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const ::dmgplace::Error& e) {
    return e.what();
  }
  return "(no dmgplace::Error)";
}

}  // namespace dmgplace::test

// Skips the test when ../shared/datasets is missing (CI always has it).
#define DMGPLACE_REQUIRE_SHARED()                                                             \
  do {                                                                                        \
    if (::dmgplace::test::shared_datasets().empty()) GTEST_SKIP() << "no ../shared/datasets"; \
  } while (0)
