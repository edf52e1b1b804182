#pragma once
// Text embedded at build time (cmake/EmbedViewerAssets.cmake): three.js from the npm registry and
// the viewer page's own HTML template and script (tools/src/viewer/page).
#include <string_view>

namespace dmgplace::tools::viewer {

std::string_view three_version();
std::string_view three_module_js();    // build/three.module.min.js (ES module)
std::string_view orbit_controls_js();  // examples/jsm/controls/OrbitControls.js, imports 'three'
std::string_view page_html();          // template with the @MARKERS@ viewer_page.cpp fills
std::string_view page_js();            // the page's module script

}  // namespace dmgplace::tools::viewer
