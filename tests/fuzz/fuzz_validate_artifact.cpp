// libFuzzer target: validate_artifact (any kind: header, every checksum, semantic checks).
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/error.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = dmgplace::fuzz::write_input(data, size, "input.h5");
  try {
    dmgplace::formats::validate_artifact(path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
