// libFuzzer target: load_object (HDF5 header, schema, shapes, checksums, object invariants).
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = dmgplace::fuzz::write_input(data, size, "input.h5");
  try {
    dmgplace::formats::load_object(path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
