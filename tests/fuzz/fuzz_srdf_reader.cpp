// libFuzzer target: apply_srdf on the built-in dmgarm robot (read once from datasets/).
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const dmgplace::RobotModel robot =
      dmgplace::tools::read_urdf(DMGPLACE_SOURCE_DIR "/datasets/robots/dmgarm/dmgarm.urdf");
  const auto path = dmgplace::fuzz::write_input(data, size, "input.srdf");
  dmgplace::RobotModel model = robot;
  try {
    dmgplace::tools::apply_srdf(model, path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
