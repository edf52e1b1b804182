#include "dmgplace/tools/viewer/viewer_page.hpp"

#include <stdexcept>
#include <string_view>

#include "dmgplace/tools/viewer/base64.hpp"
#include "dmgplace/tools/viewer/viewer_assets.hpp"

namespace dmgplace::tools::viewer {
namespace {

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

std::string data_url(std::string_view js) { return "data:text/javascript;base64," + base64(js.data(), js.size()); }

}  // namespace

std::string viewer_page(const std::string& title, const std::string& data_json) {
  const std::string import_map = R"({"imports": {"three": ")" + data_url(three_module_js()) +
                                 R"(", "three/addons/controls/OrbitControls.js": ")" + data_url(orbit_controls_js()) +
                                 "\"}}";
  const std::string_view tpl = page_html();
  // One pass over the template, so marker-like text inside what is inserted stays untouched.
  std::string out;
  out.reserve(tpl.size() + import_map.size() + data_json.size() + page_js().size());
  std::size_t pos = 0;
  while (true) {
    const std::size_t at = tpl.find('@', pos);
    if (at == std::string_view::npos) break;
    const std::size_t end = tpl.find('@', at + 1);
    if (end == std::string_view::npos) break;
    const std::string_view name = tpl.substr(at + 1, end - at - 1);
    std::string value;
    if (name == "TITLE") value = html_escape(title);
    else if (name == "THREE_VERSION") value = std::string(three_version());
    else if (name == "IMPORTMAP") value = import_map;
    else if (name == "DATA") value = data_json;
    else if (name == "PAGE_JS") value = std::string(page_js());
    else {  // a lone '@' in the template: keep it and look on from the next one
      out.append(tpl.substr(pos, end - pos));
      pos = end;
      continue;
    }
    out.append(tpl.substr(pos, at - pos));
    out += value;
    pos = end + 1;
  }
  out.append(tpl.substr(pos));
  return out;
}

}  // namespace dmgplace::tools::viewer
