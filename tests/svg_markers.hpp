#pragma once
// The conflict markers of a conflict map's SVG (models/highway/conflict_map.py): one group
// <g id="conflicts_TYPE_PANEL"> per conflict type and panel; a marker is a <use> or a <path>
// outside the group's <defs> (matplotlib writes either form).
#include <string>

namespace st::test {

inline long svgMarkers(const std::string& svg) {
  long n = 0;
  std::size_t at = 0;
  while ((at = svg.find("<g id=\"conflicts_", at)) != std::string::npos) {
    // the group ends at its matching </g>
    int depth = 0;
    std::size_t i = at, end = svg.size();
    while (i < svg.size()) {
      const std::size_t open = svg.find("<g", i + 1), close = svg.find("</g>", i + 1);
      if (close == std::string::npos) break;
      if (open != std::string::npos && open < close) {
        ++depth;
        i = open;
      } else if (depth == 0) {
        end = close;
        break;
      } else {
        --depth;
        i = close;
      }
    }
    std::string group = svg.substr(at, end - at);
    for (std::size_t d; (d = group.find("<defs>")) != std::string::npos;) {
      const std::size_t e = group.find("</defs>", d);
      group.erase(d, (e == std::string::npos ? group.size() : e + 7) - d);
    }
    for (const char* tag : {"<use ", "<path "})
      for (std::size_t k = 0; (k = group.find(tag, k)) != std::string::npos; ++k) ++n;
    at = end;
  }
  return n;
}

}  // namespace st::test
