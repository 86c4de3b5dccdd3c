#pragma once
// Writing the printable mesh: the format follows the file's extension (binary STL, 3MF, OBJ, binary
// little-endian PLY). Coordinates are written as millimetres (3MF states it in the file; the others
// have no unit field, and slicers assume millimetres). Every write is atomic: no partial file.

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "geometry/mesh.hpp"

namespace poreshell {

// Lower-case extensions write_mesh accepts, for messages: ".stl, .3mf, .obj, .ply".
std::string supported_output_extensions();

// Throws InputError naming the supported extensions if `path`'s extension is not one of them.
// Cheap: the pipeline calls it before the solve.
void check_output_extension(const std::filesystem::path& path);

// Writes `mesh` (millimetres) in the format of `path`'s extension.
void write_mesh(const std::filesystem::path& path, const TriangleMesh& mesh);

void write_3mf(const std::filesystem::path& path, const TriangleMesh& mesh);
void write_obj(const std::filesystem::path& path, const TriangleMesh& mesh);
// Binary little-endian PLY. Given a pattern (one value per vertex, a preview's surface), with vertex
// colours (red, green, blue bytes): dark where pattern > level (a hole), light elsewhere, blended over
// |pattern - level| < 0.1.
void write_ply(const std::filesystem::path& path, const TriangleMesh& mesh,
               std::span<const double> pattern = {}, double level = 0.0);
// The colour write_ply gives a vertex.
std::array<std::uint8_t, 3> pattern_colour(double value, double level);

}  // namespace poreshell
