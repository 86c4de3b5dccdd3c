#pragma once
// Reading point clouds: XYZ text ("x y z" a line, extra columns such as normals ignored, '#' comments)
// and PLY vertices (ASCII or binary, io/ply_reader). A PLY that also has faces keeps them: the paper's
// route densifies those triangular patches (section 3.4, Fig. 8).

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/types.hpp"

namespace poreshell {

struct PointCloud {
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;  // optional patches over `points`; empty for raw points
};

// Reads a point cloud; the extension picks the format (.xyz, .txt, .pts: text; .ply). Throws InputError
// for a missing, empty, truncated or unreadable file and for NaN/inf coordinates.
PointCloud read_point_cloud(const std::filesystem::path& path);

// The same from a file's bytes: `extension` (".xyz", ".ply", ...) picks the format, `name` is the file's
// name in messages.
PointCloud read_point_cloud_bytes(std::string_view bytes, const std::string& extension,
                                  const std::string& name);

}  // namespace poreshell
