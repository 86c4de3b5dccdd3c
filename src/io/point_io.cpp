#include "io/point_io.hpp"

// XYZ text is parsed here (Assimp's XYZ support is not in Debian's build). PLY goes through
// io/ply_reader, not Assimp: Assimp's PLY importer crashed or ran for more than 30 s on small crafted
// point clouds, and filled a truncated binary file with zeros silently (docs/reliability.md).

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "io/file_bytes.hpp"
#include "io/file_format.hpp"
#include "io/ply_reader.hpp"
#include "io/text_scan.hpp"

namespace poreshell {
namespace {

void check_finite(const Vec3& p, const std::string& name, std::size_t index) {
  if (!p.allFinite())
    throw InputError(fmt::format(
        "point file '{}': point {} has a NaN or infinite coordinate ({}, {}, {}); remove or fix it", name,
        index + 1, p.x(), p.y(), p.z()));
}

// Commas and semicolons separate numbers too (CSV exports).
std::string_view next_number_token(std::string_view& line) {
  std::size_t i = 0;
  while (i < line.size() && (text::is_space(line[i]) || line[i] == ',' || line[i] == ';')) ++i;
  std::size_t j = i;
  while (j < line.size() && !text::is_space(line[j]) && line[j] != ',' && line[j] != ';') ++j;
  const std::string_view token = line.substr(i, j - i);
  line.remove_prefix(j);
  return token;
}

PointCloud read_xyz(std::string_view bytes, const std::string& name) {
  PointCloud cloud;
  text::Lines lines(bytes);
  for (std::string_view line; lines.next(line);) {
    std::string_view rest = line;
    const std::string_view first = next_number_token(rest);
    if (first.empty() || first[0] == '#') continue;
    rest = line;
    Vec3 p;
    for (int a = 0; a < 3; ++a) {
      const std::string_view token = next_number_token(rest);
      if (!text::parse_double(token, p[a]))
        throw InputError(fmt::format(
            "point file '{}', line {}: expected three numbers 'x y z', got '{}'; give one point a line", name,
            lines.number(), text::quote(line, 60)));
    }
    check_finite(p, name, cloud.points.size());
    cloud.points.push_back(p);  // further columns (normals, colours, comments) are ignored
  }
  return cloud;
}

bool is_text(const std::string& extension) {
  return extension == ".xyz" || extension == ".txt" || extension == ".pts";
}

void check_extension(const std::string& extension, const std::string& name) {
  if (!is_text(extension) && extension != ".ply")
    throw InputError(fmt::format(
        "unknown point file extension '{}' of '{}': use .xyz (text, x y z a line) or .ply; for a triangle "
        "mesh use --mesh",
        text::quote(extension), name));
}

PointCloud read_ply(std::string_view bytes, const std::string& name) {
  ply::Data data = ply::read(bytes, name);
  for (std::size_t i = 0; i < data.vertices.size(); ++i) check_finite(data.vertices[i], name, i);
  return PointCloud{std::move(data.vertices), std::move(data.triangles)};
}

}  // namespace

PointCloud read_point_cloud_bytes(std::string_view bytes, const std::string& extension,
                                  const std::string& name) {
  check_extension(extension, name);
  if (bytes.empty())
    throw InputError(fmt::format(
        "point file '{}' is empty (0 bytes): give a file with one 'x y z' point a line or a PLY", name));
  PointCloud cloud = is_text(extension) ? read_xyz(bytes, name) : read_ply(bytes, name);
  if (cloud.points.empty())
    throw InputError(fmt::format("point file '{}' holds no points: give at least one 'x y z' point", name));
  if (cloud.points.size() > static_cast<std::size_t>(INT32_MAX))
    throw InputError(fmt::format("point file '{}' has more than 2^31 points: subsample it", name));
  return cloud;
}

PointCloud read_point_cloud(const std::filesystem::path& path) {
  const std::string ext = lowercase_extension(path);
  check_extension(ext, path.string());  // before a large file of an unknown format is read
  return read_point_cloud_bytes(read_file_bytes(path, "point"), ext, path.string());
}

}  // namespace poreshell
