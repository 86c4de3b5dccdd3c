#pragma once
// Binary STL in and out. Writing is atomic (temporary file, then rename): a failed write leaves
// no partial file behind.

#include <filesystem>

#include "geometry/mesh.hpp"

namespace poreshell {

void write_stl_binary(const std::filesystem::path& path, const TriangleMesh& mesh);

// Reads a binary STL and welds identical vertices (exact coordinate match).
TriangleMesh read_stl_binary(const std::filesystem::path& path);

}  // namespace poreshell
