#include "io/point_io.hpp"

// XYZ text is parsed here (Assimp's XYZ support is not in Debian's build). PLY goes through Assimp,
// which reads vertex-only files as a point mesh, but fills a truncated binary file with zeros
// silently; a short header check in front (ply_header.hpp) catches that.

#include <fmt/format.h>

#include <assimp/scene.h>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <fstream>
#include <string>
#include <system_error>

#include "core/error.hpp"
#include "io/file_format.hpp"
#include "io/ply_header.hpp"

namespace poreshell {
namespace {

void check_finite(const Vec3& p, const std::filesystem::path& path, std::size_t index) {
  if (!p.allFinite())
    throw InputError(
        fmt::format("point file '{}': point {} has a NaN or infinite coordinate; remove or fix it",
                    path.string(), index + 1));
}

// strtod accepts "nan" and "inf", so that NaN points are reported as such rather than as unreadable.
bool parse_number(const char*& s, double& out) {
  while (*s == ' ' || *s == '\t' || *s == ',' || *s == ';') ++s;
  char* end = nullptr;
  out = std::strtod(s, &end);
  if (end == s) return false;
  s = end;
  return true;
}

PointCloud read_xyz(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("cannot open point file '{}': check the path", path.string()));
  PointCloud cloud;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const char* s = line.c_str() + first;
    Vec3 p;
    for (int a = 0; a < 3; ++a)
      if (!parse_number(s, p[a]))
        throw InputError(fmt::format("point file '{}', line {}: expected three numbers 'x y z', got '{}'",
                                     path.string(), number, line.substr(0, 60)));
    check_finite(p, path, cloud.points.size());
    cloud.points.push_back(p);  // further columns (normals, colours) are ignored
  }
  return cloud;
}

// The bytes the header promises for the elements up to and including "vertex", when that much is
// computable (no list property before it). Compared with the file size to catch a truncated file.
void check_ply_length(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const ply::Header header = ply::read_header(in, path);
  std::size_t promised = 0, vertex_count = 0;
  bool computable = true;
  for (const ply::Element& element : header.elements) {
    const auto row_bytes = element.row_bytes();
    computable = computable && row_bytes.has_value();
    if (computable) promised += element.count * *row_bytes;
    if (element.name == "vertex") {
      vertex_count = element.count;
      break;
    }
  }
  if (vertex_count == 0)
    throw InputError(fmt::format("PLY file '{}' has no vertices: give a point cloud with at least one point",
                                 path.string()));
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return;
  if (header.format == ply::Format::ascii) {
    // One vertex a line: count the lines after the header (vertices come first in every common file).
    std::size_t lines = 0;
    std::string line;
    while (lines < vertex_count && std::getline(in, line))
      if (line.find_first_not_of(" \t\r") != std::string::npos) ++lines;
    if (lines < vertex_count)
      throw InputError(fmt::format("PLY file '{}' is truncated: its header promises {} vertices, it holds {}",
                                   path.string(), vertex_count, lines));
  } else if (computable && header.bytes + promised > size) {
    throw InputError(
        fmt::format("PLY file '{}' is truncated: its header promises {} bytes of data, it holds {}",
                    path.string(), promised, size - std::min<std::uintmax_t>(size, header.bytes)));
  }
}

void append_node(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, PointCloud& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const std::size_t base = out.points.size();
    if (base + mesh.mNumVertices > static_cast<std::size_t>(INT32_MAX))
      throw InputError("the point cloud has more than 2^31 points: subsample it");
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out.points.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      // Polygons become fans; points and lines carry no patch.
      for (unsigned k = 2; k < face.mNumIndices; ++k)
        out.triangles.push_back({static_cast<std::int32_t>(base + face.mIndices[0]),
                                 static_cast<std::int32_t>(base + face.mIndices[k - 1]),
                                 static_cast<std::int32_t>(base + face.mIndices[k])});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) append_node(scene, *node.mChildren[c], transform, out);
}

PointCloud read_ply(const std::filesystem::path& path) {
  check_ply_length(path);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  if (scene == nullptr || scene->mRootNode == nullptr)
    throw InputError(fmt::format("cannot read PLY file '{}': {}; check that it is a complete, valid PLY file",
                                 path.string(), importer.GetErrorString()));
  PointCloud cloud;
  append_node(*scene, *scene->mRootNode, aiMatrix4x4(), cloud);
  for (std::size_t i = 0; i < cloud.points.size(); ++i) check_finite(cloud.points[i], path, i);
  return cloud;
}

}  // namespace

PointCloud read_point_cloud(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(
        fmt::format("point file '{}' does not exist or is not a file: check the path", path.string()));
  if (std::filesystem::file_size(path, ec) == 0 || ec)
    throw InputError(fmt::format(
        "point file '{}' is empty: give a file with one 'x y z' point a line or a PLY", path.string()));
  const std::string ext = lowercase_extension(path);
  PointCloud cloud;
  if (ext == ".xyz" || ext == ".txt" || ext == ".pts")
    cloud = read_xyz(path);
  else if (ext == ".ply")
    cloud = read_ply(path);
  else
    throw InputError(fmt::format(
        "unknown point file extension '{}' of '{}': use .xyz (text, x y z a line) or .ply; for a triangle "
        "mesh use --mesh",
        ext, path.string()));
  if (cloud.points.empty())
    throw InputError(
        fmt::format("point file '{}' holds no points: give at least one 'x y z' point", path.string()));
  return cloud;
}

}  // namespace poreshell
