#pragma once
// Reading triangle meshes from files (STL, OBJ, PLY, OFF by poreshell's readers; 3MF through lib3mf) and the
// clean-up every imported mesh gets: exact welding, unused vertices removed, degenerate triangles
// dropped. Scans with holes and open surfaces are accepted as they are.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "geometry/mesh.hpp"

namespace poreshell {

struct MeshInputStats {
  std::int64_t vertices = 0;            // after welding exact duplicates and removing unused ones
  std::int64_t triangles = 0;           // after dropping degenerate ones
  std::int64_t dropped_degenerate = 0;  // repeated vertex or zero area
  std::int64_t boundary_edges = 0;      // edges with one triangle (holes, open borders)
  std::int64_t dropped_duplicate = 0;   // a triangle on the same three vertices as an earlier one
};

// Welds vertices with identical coordinates, removes unused vertices and drops degenerate triangles and
// repeats of a triangle (the same three vertices, either orientation).
// Throws InputError if a used vertex is NaN/inf or nothing is left.
MeshInputStats clean_triangle_mesh(TriangleMesh& mesh);

// Reads and cleans a mesh; the extension picks the format. Throws InputError with the reason.
TriangleMesh read_triangle_mesh(const std::filesystem::path& path, MeshInputStats* stats = nullptr);

// The same from a file's bytes: `extension` (".stl", ...) picks the format, `name` is the file's name in
// messages.
TriangleMesh read_triangle_mesh_bytes(std::string_view bytes, const std::string& extension,
                                      const std::string& name, MeshInputStats* stats = nullptr);

}  // namespace poreshell
