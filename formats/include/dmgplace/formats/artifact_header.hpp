#pragma once
// What every artifact carries at its root, whatever its kind.
#include <string>
#include <vector>

namespace dmgplace::formats {

struct InputFile {
  std::string path;    // as given on the command line
  std::string sha256;  // of the file's bytes
};

struct ArtifactHeader {
  std::string schema;  // "dmgplace.object", "dmgplace.environment", "dmgplace.robot"
  int schema_version = 0;
  std::string tool_version;     // dmgplace version that wrote it
  std::string created_utc;      // ISO 8601
  std::string parameters_json;  // creation parameters as a JSON object
  std::vector<InputFile> inputs;
  // Not stored: the file this artifact was read from (empty when built in memory), so errors
  // found after loading can still name it.
  std::string source_file;
};

// The version string of this build, e.g. "0.1.0".
const char* tool_version();
// Current UTC time as ISO 8601.
std::string utc_now_iso8601();

}  // namespace dmgplace::formats
