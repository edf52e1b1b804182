// libFuzzer target: read_placement_query (QUERY.yaml of `dmgplace place`), then resolve_start on
// the built-in dmgarm arm (read once from datasets/), so list and named starts are both checked.
#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/placement/placement_query_file.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const dmgplace::runtime::Kinematics kin(
      dmgplace::tools::read_urdf(DMGPLACE_SOURCE_DIR "/datasets/robots/dmgarm/dmgarm.urdf"), "dmgarm_link0",
      "dmgarm_tcp");
  const auto path = dmgplace::fuzz::write_input(data, size, "input.yaml");
  try {
    const auto query = dmgplace::tools::read_placement_query(path);
    dmgplace::tools::resolve_start(query, kin);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
