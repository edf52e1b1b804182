// libFuzzer target: read_urdf (urdfdom + our conversion), then read_urdf_scene's placement of the
// same file. Mesh references resolve relative to the scratch folder (only the input itself).
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = dmgplace::fuzz::write_input(data, size, "input.urdf");
  try {
    const dmgplace::RobotModel model = dmgplace::tools::read_urdf(path);
    if (!model.links.empty()) dmgplace::tools::read_urdf_scene(path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
