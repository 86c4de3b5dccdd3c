// Writes the browser tests' page (viewer_test_data) and what the tests expect of it, as JSON:
//   make_viewer_page PAGE.html EXPECTED.json [preview]
// With `preview`: the page of a preview (the surface with its holes painted on, no solid).
#include <fstream>
#include <iostream>
#include <string>

#include "viewer_test_data.hpp"

int main(int argc, char** argv) {
  const bool preview = argc == 4 && std::string(argv[3]) == "preview";
  if (argc != 3 && !preview) {
    std::cerr << "usage: make_viewer_page PAGE.html EXPECTED.json [preview]\n";
    return 2;
  }
  const poreshell::ViewerData data = poreshell::testing::viewer_test_data(40, preview);
  poreshell::write_html_viewer(argv[1], data);
  nlohmann::json holes = nlohmann::json::array();
  for (const poreshell::ViewerHole& h : data.holes)
    holes.push_back({{"centre", {h.centre.x(), h.centre.y(), h.centre.z()}},
                     {"normal", {h.normal.x(), h.normal.y(), h.normal.z()}},
                     {"diameter_mm", h.diameter_mm},
                     {"asked_mm", h.asked_mm}});
  // A point on the sphere (centre (10, -5, 20), radius 40) away from every hole, for the surface click.
  std::ofstream(argv[2]) << nlohmann::json{{"preview", preview},
                                           {"hole_count", data.holes.size()},
                                           {"holes", holes},
                                           {"sphere", {{"centre", {10.0, -5.0, 20.0}}, {"radius", 40.0}}},
                                           {"fold_radius", preview ? 0.0 : poreshell::testing::kFoldRadius}}
                                .dump(1);
  return 0;
}
