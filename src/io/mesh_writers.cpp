#include "io/mesh_writers.hpp"

// All formats store float32 coordinates (OBJ and 3MF write each float's shortest exact decimal), so
// every format carries exactly the geometry of the binary STL.

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/file_format.hpp"
#include "io/stl.hpp"
#include "io/zip_writer.hpp"

namespace poreshell {
namespace {

void check_size(const std::filesystem::path& path, const TriangleMesh& mesh) {
  if (mesh.triangles.empty())
    throw InputError("refusing to write '" + path.string() + "': the mesh is empty");
  if (mesh.vertices.size() > std::numeric_limits<std::uint32_t>::max() ||
      mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    throw InputError("the mesh is too large to write; use a larger voxel size");
}

void put_u32(std::vector<char>& out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((v >> (8 * b)) & 0xFFu));
}

// 3MF (core specification): the model as XML in a ZIP package with its content types and relationship.
// Written by hand (zip_writer.hpp) rather than through lib3mf, whose writer formats and deflates on one
// thread; the text is lib3mf's, less its indentation and its random production-extension UUIDs.
constexpr std::size_t k3mfLinesPerChunk = 1 << 15;  // about 1.5 MB of text: a few chunks per thread

constexpr const char* k3mfContentTypes =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
    "<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
    "<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
    "</Types>\n";
constexpr const char* k3mfRelationships =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
    "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
    "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n";
constexpr const char* k3mfModelStart =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<model unit=\"millimeter\" xml:lang=\"en-US\" "
    "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n"
    "<metadata name=\"Application\">poreshell " PORESHELL_VERSION
    "</metadata>\n"
    "<resources>\n<object id=\"1\" name=\"poreshell porous shell\" type=\"model\">\n<mesh>\n<vertices>\n";
constexpr const char* k3mfBetween = "</vertices>\n<triangles>\n";
constexpr const char* k3mfModelEnd =
    "</triangles>\n</mesh>\n</object>\n</resources>\n<build>\n<item objectid=\"1\"/>\n</build>\n</model>\n";

// The shortest decimal that reads back as the same float, never in exponent form (some readers' number
// parsers are simple).
void append_coordinate(std::string& text, double value) {
  char buffer[64];  // the longest, FLT_MIN's denormals, take 47 characters
  const auto [end, error] =
      std::to_chars(buffer, buffer + sizeof buffer, static_cast<float>(value), std::chars_format::fixed);
  if (error != std::errc()) throw std::runtime_error("a 3MF coordinate could not be formatted");
  text.append(buffer, end);
}

void append_index(std::string& text, std::int64_t index) {
  char buffer[24];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, index);
  if (error != std::errc()) throw std::runtime_error("a 3MF index could not be formatted");
  text.append(buffer, end);
}

}  // namespace

std::string supported_output_extensions() {
  return ".stl, .3mf, .obj, .ply";
}

void check_output_extension(const std::filesystem::path& path) {
  const std::string ext = lowercase_extension(path);
  if (ext != ".stl" && ext != ".3mf" && ext != ".obj" && ext != ".ply")
    throw InputError(
        fmt::format("cannot write '{}': unknown output format '{}'; name the output with one of {}",
                    path.string(), ext, supported_output_extensions()));
}

void write_mesh(const std::filesystem::path& path, const TriangleMesh& mesh) {
  check_output_extension(path);
  const std::string ext = lowercase_extension(path);
  if (ext == ".stl")
    write_stl_binary(path, mesh);
  else if (ext == ".3mf")
    write_3mf(path, mesh);
  else if (ext == ".obj")
    write_obj(path, mesh);
  else
    write_ply(path, mesh);
}

void write_3mf(const std::filesystem::path& path, const TriangleMesh& mesh) {
  check_size(path, mesh);
  const std::size_t vertex_chunks = (mesh.vertices.size() + k3mfLinesPerChunk - 1) / k3mfLinesPerChunk;
  const std::size_t triangle_chunks = (mesh.triangles.size() + k3mfLinesPerChunk - 1) / k3mfLinesPerChunk;
  // Chunks: the model's start, the vertices', the text between, the triangles', the end.
  const auto model_text = [&](std::size_t chunk, std::string& text) {
    if (chunk == 0) {
      text += k3mfModelStart;
      return;
    }
    if (chunk == 1 + vertex_chunks) {
      text += k3mfBetween;
      return;
    }
    if (chunk == 2 + vertex_chunks + triangle_chunks) {
      text += k3mfModelEnd;
      return;
    }
    const bool vertices = chunk <= vertex_chunks;
    const std::size_t first = (chunk - (vertices ? 1 : 2 + vertex_chunks)) * k3mfLinesPerChunk;
    const std::size_t count = vertices ? mesh.vertices.size() : mesh.triangles.size();
    const std::size_t last = std::min(count, first + k3mfLinesPerChunk);
    text.reserve(56 * (last - first));
    for (std::size_t i = first; i < last; ++i) {
      if (vertices) {
        const Vec3& v = mesh.vertices[i];
        text += "<vertex x=\"";
        append_coordinate(text, v.x());
        text += "\" y=\"";
        append_coordinate(text, v.y());
        text += "\" z=\"";
        append_coordinate(text, v.z());
      } else {
        const auto& t = mesh.triangles[i];
        text += "<triangle v1=\"";
        append_index(text, t[0]);
        text += "\" v2=\"";
        append_index(text, t[1]);
        text += "\" v3=\"";
        append_index(text, t[2]);
      }
      text += "\"/>\n";
    }
  };
  const auto fixed_text = [](const char* content) {
    return [content](std::size_t, std::string& text) { text += content; };
  };
  const std::vector<ZipEntry> entries{
      {"[Content_Types].xml", 1, fixed_text(k3mfContentTypes)},
      {"_rels/.rels", 1, fixed_text(k3mfRelationships)},
      {"3D/3dmodel.model", 3 + vertex_chunks + triangle_chunks, model_text},
  };
  write_atomically(path, [&](std::ostream& out) { write_zip(out, entries); });
}

void write_obj(const std::filesystem::path& path, const TriangleMesh& mesh) {
  check_size(path, mesh);
  write_atomically(
      path,
      [&](std::ostream& out) {
        out << "# poreshell porous shell, millimetres\n";
        fmt::memory_buffer buffer;
        for (const Vec3& v : mesh.vertices)
          fmt::format_to(std::back_inserter(buffer), "v {} {} {}\n", static_cast<float>(v.x()),
                         static_cast<float>(v.y()), static_cast<float>(v.z()));
        for (const auto& t : mesh.triangles)  // OBJ counts vertices from 1
          fmt::format_to(std::back_inserter(buffer), "f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      },
      false);
}

std::array<std::uint8_t, 3> pattern_colour(double value, double level) {
  static constexpr std::array<double, 3> solid{216, 210, 200}, open{58, 63, 71};
  const double t = std::clamp((value - level) / 0.2 + 0.5, 0.0, 1.0);  // 0 solid .. 1 open
  std::array<std::uint8_t, 3> c{};
  for (std::size_t i = 0; i < 3; ++i)
    c[i] = static_cast<std::uint8_t>(std::lround((1.0 - t) * solid[i] + t * open[i]));
  return c;
}

void write_ply(const std::filesystem::path& path, const TriangleMesh& mesh, std::span<const double> pattern,
               double level) {
  check_size(path, mesh);
  const bool coloured = !pattern.empty();
  if (coloured && pattern.size() != mesh.vertices.size())
    throw InputError(
        fmt::format("the pattern has {} values for {} vertices", pattern.size(), mesh.vertices.size()));
  write_atomically(path, [&](std::ostream& out) {
    const std::string header = fmt::format(
        "ply\nformat binary_little_endian 1.0\ncomment {}\n"
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n{}"
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        coloured ? "poreshell preview, millimetres; dark: holes" : "poreshell porous shell, millimetres",
        mesh.vertices.size(),
        coloured ? "property uchar red\nproperty uchar green\nproperty uchar blue\n" : "",
        mesh.triangles.size());
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    // Bytes assembled explicitly, so the file does not depend on the host's byte order.
    std::vector<char> body;
    body.reserve((coloured ? 15 : 12) * mesh.vertices.size() + 13 * mesh.triangles.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      for (int d = 0; d < 3; ++d)
        put_u32(body, std::bit_cast<std::uint32_t>(static_cast<float>(mesh.vertices[v][d])));
      if (coloured)
        for (const std::uint8_t c : pattern_colour(pattern[v], level)) body.push_back(static_cast<char>(c));
    }
    for (const auto& t : mesh.triangles) {
      body.push_back(3);
      for (std::int32_t index : t) put_u32(body, static_cast<std::uint32_t>(index));
    }
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
}

}  // namespace poreshell
