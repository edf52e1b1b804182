// libFuzzer target: read_mesh (assimp + clean_mesh). The first byte picks the file extension
// (STL ascii/binary, OBJ, PLY); the rest is the file. Only dmgplace::Error is an accepted outcome.
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExt[] = {"stl", "obj", "ply"};
  const std::string name = std::string("input.") + kExt[data[0] % 3];
  const auto path = dmgplace::fuzz::write_input(data + 1, size - 1, name);
  try {
    dmgplace::tools::read_mesh(path);
  } catch (const dmgplace::Error&) {
  }
  return 0;
}
