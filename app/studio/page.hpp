#pragma once
// The studio's page: studio/index.html with the viewer's styles, three.js and studio/studio.js inside
// it (embedded in the program at build time), so that it makes no request but to the studio's API.

#include <string>

namespace studio {

const std::string& studio_page();

}  // namespace studio
