#include "page.hpp"

#include <string_view>

#include "studio_assets.hpp"

namespace studio {
namespace {

void replace(std::string& text, std::string_view marker, std::string_view with) {
  const std::size_t at = text.find(marker);
  if (at != std::string::npos) text.replace(at, marker.size(), with);
}

std::string script(std::string_view code) {
  return "<script>\n" + std::string(code) + "\n</script>\n";
}

}  // namespace

const std::string& studio_page() {
  static const std::string page = [] {
    namespace e = poreshell::embedded;
    std::string html(e::studio_html);
    replace(html, "@STYLE@", std::string(e::studio_viewer_css) + "\n" + std::string(e::studio_css));
    replace(html, "@SCRIPTS@",
            script(e::studio_three_js) + script(e::studio_orbit_js) + script(e::studio_js));
    return html;
  }();
  return page;
}

}  // namespace studio
