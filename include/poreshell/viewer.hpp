#pragma once
// The viewer: the result as one self-contained HTML page (three.js inside, no network) and a picture of
// it. Compiled in a library of its own (src/viewer/) that libporeshell exports, so that the core the
// stages share carries neither the page nor three.js. Errors are poreshell::Error.

#include <cstddef>
#include <filesystem>
#include <string>

#include "poreshell/export.hpp"
#include "poreshell/geometry.hpp"
#include "poreshell/options.hpp"
#include "poreshell/result.hpp"

namespace poreshell {

struct ViewOptions {
  std::string title;                   // default: the input's name
  double density_g_per_cm3 = 1.24;     // for the mass shown (PLA); editable on the page
  std::size_t max_triangles = 300000;  // the shown mesh is reduced to this; the printed one never is
  std::size_t output = 0;              // which pore level of the result
  // The axis shown pointing up, 'x', 'y' or 'z' (a button on the page turns it); 0: y for an OBJ or PLY
  // input, whose scans are mostly y up (the Stanford scans, photogrammetry, Blender's OBJ export), z for
  // the rest (STL and 3MF for printing: the build plate's z).
  char up = 0;
};

// The interactive viewer: one self-contained HTML file (no network) with the mesh, the holes coloured by
// their diameter's deviation from the request, rims and keep-outs outlined, the measured figures and a
// histogram; clicking shows a hole's figures or a point's coordinates in the input frame (mm). `input`,
// when given, outlines the open boundary the rim runs along.
PORESHELL_API void save_html(const std::filesystem::path& path, const Result& result, const Options& options,
                             const Input* input = nullptr, const ViewOptions& view = {});
// A picture of the page through headless Chromium; Error(io) naming the fix where it is not installed.
PORESHELL_API void save_png(const std::filesystem::path& html, const std::filesystem::path& png);

}  // namespace poreshell
