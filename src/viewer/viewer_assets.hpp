#pragma once
// The viewer page's parts, embedded at build time (cmake/EmbedFiles.cmake; see src/viewer/CMakeLists.txt):
// viewer/ of this repository and three.js r111 with its OrbitControls from Debian's libjs-three.

#include <string_view>

namespace poreshell::embedded {

extern const std::string_view viewer_html;        // viewer/index.html, the template
extern const std::string_view viewer_css;         // viewer/viewer.css
extern const std::string_view viewer_js;          // viewer/viewer.js
extern const std::string_view three_js;           // three.min.js
extern const std::string_view orbit_controls_js;  // examples/js/controls/OrbitControls.js

}  // namespace poreshell::embedded
