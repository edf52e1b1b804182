// libFuzzer target, structure-aware: each input is a list of edits to sound artifacts (the .h5
// files in $DMGPLACE_FUZZ_BASES, which scripts/fuzz bakes), applied with every checksum
// recomputed. Byte-level mutations almost always stop at a checksum; these reach the loaders'
// semantic gate and, past it, the runtime structures built from a loaded artifact.
// One edit = 16 bytes: file (1), dataset (2), element (4), value kind (1), value (8).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "artifact_mutation.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/grasp/reachable_grasps.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "fuzz_input.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;

namespace {

struct Base {
  fs::path path;
  std::vector<std::string> datasets;
  std::vector<std::size_t> sizes;
};
std::vector<Base> bases;

double pick_value(std::uint8_t kind, double raw, double old) {
  switch (kind % 12) {
    case 0:
      return std::numeric_limits<double>::quiet_NaN();
    case 1:
      return std::numeric_limits<double>::infinity();
    case 2:
      return -std::numeric_limits<double>::infinity();
    case 3:
      return 0;
    case 4:
      return -1;
    case 5:
      return 1e300;
    case 6:
      return 2147483647.0;
    case 7:
      return old + 0.1;  // plausible but wrong: a region raised, a face shifted
    case 8:
      return old * -1;
    case 9:
      return old + 1;  // an index one past
    case 10:
      return std::isfinite(raw) ? raw : 0;
    default:
      return old * 1e6;
  }
}

// Load what the edited file is, and use it the way the runtime does.
void exercise(const fs::path& p) {
  (void)formats::validate_artifact(p);
  try {
    const std::string schema = formats::H5Reader(p).header().schema;
    if (schema == formats::kObjectSchema) {
      const auto o = formats::load_object(p);
      const runtime::GraspGraph g(o);
      (void)runtime::reachable_grasps(g, Eigen::Isometry3d::Identity());
    } else if (schema == formats::kRobotSchema) {
      const auto r = formats::load_robot(p);
      const runtime::Kinematics k(r.model, r.model.arm_base, r.model.arm_tip);
      std::vector<Eigen::Isometry3d> poses;
      k.link_poses(0.5 * (k.lower() + k.upper()), poses);
    } else if (schema == formats::kEnvironmentSchema) {
      (void)formats::load_environment(p);
    }
  } catch (const Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* dir = std::getenv("DMGPLACE_FUZZ_BASES");
  if (!dir) {
    std::fprintf(
        stderr, "fuzz_crafted_artifacts: set DMGPLACE_FUZZ_BASES to a folder of sound artifacts (scripts/fuzz does)\n");
    std::abort();
  }
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".h5") continue;
    Base b{e.path(), test::artifact_datasets(e.path()), {}};
    for (const auto& d : b.datasets) b.sizes.push_back(test::dataset_size(e.path(), d));
    bases.push_back(std::move(b));
  }
  if (bases.empty()) std::abort();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::size_t kEdit = 16;
  if (size < kEdit) return 0;
  const Base& base = bases[data[0] % bases.size()];
  const fs::path a = fuzz::scratch_dir() / "crafted_a.h5", b = fuzz::scratch_dir() / "crafted_b.h5";
  fs::copy_file(base.path, a, fs::copy_options::overwrite_existing);
  for (std::size_t at = 0; at + kEdit <= size && at < 8 * kEdit; at += kEdit) {
    const std::uint8_t* e = data + at;
    const std::size_t d = (std::size_t(e[1]) | std::size_t(e[2]) << 8) % base.datasets.size();
    if (base.sizes[d] == 0) continue;
    std::uint32_t element;
    std::memcpy(&element, e + 3, 4);
    double raw;
    std::memcpy(&raw, e + 8, 8);
    const std::size_t index = element % base.sizes[d];
    const double value = pick_value(e[7], raw, test::dataset_value(a, base.datasets[d], index));
    test::mutate_dataset(a, b, base.datasets[d], index, value);
    fs::rename(b, a);
  }
  exercise(a);
  return 0;
}
