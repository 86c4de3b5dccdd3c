#pragma once
// poreshell's own readers of the simple mesh formats, from bytes in memory: STL (ASCII and binary), OBJ
// and OFF. They replace Assimp's importers, which aborted (ai_assert), crashed or ran for seconds on
// small crafted files (docs/reliability.md). Each bounds its work by the input's size and throws
// InputError, naming `name`, the line and the fix, for anything malformed. The triangles index the
// vertices as stored; welding, unused vertices, NaN and degenerate triangles are left to
// clean_triangle_mesh.

#include <string>
#include <string_view>

#include "geometry/mesh.hpp"

namespace poreshell {

TriangleMesh read_stl_bytes(std::string_view bytes, const std::string& name);
TriangleMesh read_obj_bytes(std::string_view bytes, const std::string& name);
TriangleMesh read_off_bytes(std::string_view bytes, const std::string& name);

}  // namespace poreshell
