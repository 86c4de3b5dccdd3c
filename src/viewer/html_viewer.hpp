#pragma once
// The interactive viewer: one self-contained HTML file (three.js, the page's script and the data all
// inside it; it opens from file:// with no network), and its rendering to a PNG by headless Chromium.
// The page's source is viewer/ (see viewer/README.md); it is embedded in the viewer library
// (src/viewer/CMakeLists.txt) at build time.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/types.hpp"
#include "geometry/mesh.hpp"

namespace poreshell {

// The most triangles write_html_viewer takes: reduce larger meshes for display first (e.g. with
// reduce/mesh_decimate.hpp). At this size the page is about 9 MB (12 bytes a vertex and 12 a triangle,
// base64 4/3, plus 0.9 MB of three.js).
inline constexpr std::size_t html_viewer_max_triangles = 300'000;

struct ViewerHole {
  Vec3 centre = Vec3::Zero();   // mm, on the surface
  Vec3 normal = Vec3::UnitZ();  // the surface's normal there (any length; 0 when unknown)
  double diameter_mm = 0.0;
  double circularity = 1.0;           // 1 for a round hole
  double nearest_neighbour_mm = 0.0;  // centre to the nearest other hole's centre
  double axis_ratio = 1.0;            // minor over major axis of its cross-section
  double asked_mm = 0.0;              // the diameter asked at its centre (graded); 0: none asked
};

struct ViewerSphere {
  Vec3 centre = Vec3::Zero();  // mm
  double radius_mm = 0.0;
};

struct ViewerBox {
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();  // mm, two opposite corners
};

struct ViewerData {
  std::string title = "poreshell";
  // The display mesh, mm, in the input's frame (the frame of --keep-out): the page reports clicked
  // points in these coordinates. At most html_viewer_max_triangles triangles.
  TriangleMesh mesh;
  // Optional (a preview): per vertex of `mesh`, the pattern's value minus the pore level; the page
  // paints the vertices where it is positive as holes.
  std::vector<float> pattern;
  std::vector<ViewerHole> holes;
  std::optional<double> requested_diameter_mm;  // holes are coloured by their deviation from it
                                                // (from the holes' mean diameter without it)
  // Solid zones, outlined on the page.
  double rim_width_mm = 0.0;                   // shown in the panel
  std::vector<std::vector<Vec3>> rim_loops;    // optional: the open boundary's loops (mm), drawn as lines
  std::vector<ViewerSphere> keep_out_spheres;  // --keep-out X,Y,Z,R
  std::vector<ViewerBox> keep_out_boxes;       // --keep-out-box
  // The run's report (src/pipeline/report.cpp's to_json); the panel takes its figures from
  // report["mesh"] ("holes", "wall", "volume", "outputs") and report["holes"]["requested"], and
  // computes the hole figures from `holes` where the report has none. May be null.
  nlohmann::json report;
  double density_g_per_cm3 = 1.24;  // the mass's initial density (PLA); editable on the page
  int up_axis = 2;                  // the axis shown pointing up: 0 x, 1 y, 2 z (a button changes it)
};

// Writes the page to `path` atomically (temporary file, then rename). Throws InputError for a mesh
// over html_viewer_max_triangles triangles or with a vertex index out of range, or for non-finite
// coordinates; std::runtime_error if the file cannot be written.
void write_html_viewer(const std::filesystem::path& path, const ViewerData& data);

// The page as a string (what write_html_viewer writes).
std::string html_viewer_page(const ViewerData& data);

struct PngOptions {
  int width = 1600, height = 1000;  // pixels
  std::filesystem::path chromium;   // empty: $PORESHELL_CHROMIUM, else chromium, chromium-browser,
                                    // google-chrome on PATH
  int timeout_seconds = 60;
};

// Chromium's path as PngOptions::chromium would find it, or nullopt.
std::optional<std::filesystem::path> find_chromium(const std::filesystem::path& chromium = {});

// Renders a page written by write_html_viewer to a PNG (headless Chromium, software WebGL), atomically.
// Throws InputError when Chromium is not installed ("install chromium: apt-get install chromium, or
// scripts/install-deps"), std::runtime_error when it fails or times out.
void render_html_png(const std::filesystem::path& html, const std::filesystem::path& png,
                     const PngOptions& options = {});

}  // namespace poreshell
