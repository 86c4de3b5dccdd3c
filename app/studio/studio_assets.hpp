#pragma once
// The page's files, embedded by cmake/EmbedFiles.cmake (app/CMakeLists.txt).

#include <string_view>

namespace poreshell::embedded {
extern const std::string_view studio_html, studio_css, studio_js, studio_viewer_css, studio_three_js,
    studio_orbit_js;
}
