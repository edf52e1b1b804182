#pragma once
// Private to pcd_reader: validates a PCD file's header and body size before PCL reads it.
#include <string>

namespace dmgplace::tools::detail {

// dmgplace::Error unless the header is complete and self-consistent (FIELDS/SIZE/TYPE/COUNT agree,
// WIDTH x HEIGHT == POINTS > 0, DATA ascii/binary/binary_compressed) and the body holds what the
// header promises (every ascii value a number, enough binary bytes, sane compressed sizes).
void check_pcd_layout(const std::string& file);

}  // namespace dmgplace::tools::detail
