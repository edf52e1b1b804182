#pragma once
// `dmgplace validate --deep`: an artifact's numbers held against its own exact geometry. Each
// check re-derives a sampled fact the runtime's proofs rely on (field values against exact
// distances, link meshes inside their spheres, self-distance tables below the exact distance, an
// object's mass properties from its mesh) and reports its largest disagreement beside the
// tolerance it is allowed. Deterministic under `seed`; time grows with `samples`.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace dmgplace::tools {

struct DeepOptions {
  std::uint64_t seed = 1;
  int samples = 1000;         // per check (a field, a table, ...)
  bool check_inputs = false;  // also hold the artifact against the inputs its header names, where found
  int threads = 0;            // <= 0: every CPU the process may use
};

// One re-derived fact over its samples.
struct DeepCheck {
  std::string name;     // what was compared, e.g. "signed distance field at grid nodes"
  std::string dataset;  // the HDF5 dataset whose numbers were compared
  int samples = 0;
  double worst = 0;      // largest disagreement (in `unit`)
  double tolerance = 0;  // allowed disagreement (in `unit`)
  std::string unit = "m";
  std::string worst_sample;  // where the worst disagreement lies, with both values
  bool ok() const { return worst <= tolerance; }
};

struct DeepReport {
  std::string file, schema;
  std::vector<DeepCheck> checks;
  std::vector<std::string> notes;  // what was not checked and why (e.g. an input not found)
  bool ok() const;
  // One line per failed check: file, dataset, worst disagreement against its tolerance, sample.
  std::vector<std::string> problems() const;
};

// Throws dmgplace::Error when the file cannot be read or is refused by its loader (the ordinary
// validation's semantic gate).
DeepReport deep_validate(const std::filesystem::path& file, const DeepOptions& options = {});

// "name: worst W m at SAMPLE (tolerance T m, N samples)"
std::string describe(const DeepCheck& check);

}  // namespace dmgplace::tools
