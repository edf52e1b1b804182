#pragma once
// Assembles the self-contained page: the embedded template, three.js as import-map data: URLs (so
// it opens from file:// with no network), the page script and the scene data.
#include <string>

namespace dmgplace::tools::viewer {

std::string viewer_page(const std::string& title, const std::string& data_json);

}  // namespace dmgplace::tools::viewer
