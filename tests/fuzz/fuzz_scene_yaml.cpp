// libFuzzer target: read_planning_scene_yaml (MoveIt PlanningScene YAML through yaml-cpp).
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = dmgplace::fuzz::write_input(data, size, "input.yaml");
  try {
    dmgplace::tools::read_planning_scene_yaml(path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
