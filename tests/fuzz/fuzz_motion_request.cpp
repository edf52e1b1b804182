// libFuzzer target: read_motion_request (MoveIt MotionPlanRequest YAML).
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/motion_request_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = dmgplace::fuzz::write_input(data, size, "input.yaml");
  try {
    dmgplace::tools::read_motion_request(path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
