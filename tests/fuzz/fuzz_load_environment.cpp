// libFuzzer target: load_environment (HDF5 header, schema, shapes, checksums, environment invariants).
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = dmgplace::fuzz::write_input(data, size, "input.h5");
  try {
    dmgplace::formats::load_environment(path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
