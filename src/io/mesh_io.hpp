#pragma once
// Reading triangle meshes from files (STL, OBJ, PLY, OFF by poreshell's readers; 3MF through lib3mf), each
// then cleaned (geometry/mesh_clean.hpp). Scans with holes and open surfaces are accepted as they are.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "geometry/mesh_clean.hpp"

namespace poreshell {

// Reads and cleans a mesh; the extension picks the format. Throws InputError with the reason.
TriangleMesh read_triangle_mesh(const std::filesystem::path& path, MeshInputStats* stats = nullptr);

// The same from a file's bytes: `extension` (".stl", ...) picks the format, `name` is the file's name in
// messages.
TriangleMesh read_triangle_mesh_bytes(std::string_view bytes, const std::string& extension,
                                      const std::string& name, MeshInputStats* stats = nullptr);

}  // namespace poreshell
