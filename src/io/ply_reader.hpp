#pragma once
// The body of a PLY file (ASCII and both binary byte orders, any scalar type): vertices, one optional
// scalar vertex property, faces as triangle fans. One reader for meshes, point clouds and vertex fields;
// Assimp's PLY importer aborted, crashed or ran for seconds on small crafted files (docs/reliability.md).
// Every count the header gives is checked against the bytes that follow before anything is reserved.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/types.hpp"
#include "io/ply_header.hpp"

namespace poreshell::ply {

struct Data {
  std::vector<Vec3> vertices;  // as stored: NaN and inf included, for the caller to report
  std::vector<double> values;  // the requested vertex property, one per vertex; empty without one
  std::vector<std::array<std::int32_t, 3>> triangles;  // polygons as fans over `vertices`
};

// Reads the PLY file held in `bytes` (named `name` in messages). `property`: a scalar vertex property to
// read into `values`, or empty. Throws InputError for a malformed, truncated or lying file, a missing
// property (naming those the file has), no vertices, and face indices out of range.
Data read(std::string_view bytes, const std::string& name, const std::string& property = {});

// Names of the scalar properties of the file's vertices (x, y, z included); empty without vertices.
std::vector<std::string> scalar_vertex_properties(std::string_view bytes, const std::string& name);

}  // namespace poreshell::ply
