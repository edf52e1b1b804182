// libFuzzer target: read_pcd (our header/body checks, then PCL; ascii, binary, binary_compressed).
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/pcd_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = dmgplace::fuzz::write_input(data, size, "input.pcd");
  try {
    dmgplace::tools::read_pcd(path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
