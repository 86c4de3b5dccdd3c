#include "io/mesh_readers.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>

#include "core/error.hpp"
#include "io/text_scan.hpp"

namespace poreshell {
namespace {

constexpr std::size_t kStlHeaderBytes = 80, kStlFacetBytes = 50;

bool equals_lower(std::string_view token, std::string_view keyword) {
  return token.size() == keyword.size() &&
         std::equal(token.begin(), token.end(), keyword.begin(),
                    [](char a, char b) { return (a >= 'A' && a <= 'Z' ? a - 'A' + 'a' : a) == b; });
}

// Adds the polygon `corners` (vertex indices) as a fan of triangles.
void append_fan(const std::vector<std::int32_t>& corners, TriangleMesh& out) {
  for (std::size_t k = 2; k < corners.size(); ++k)
    out.triangles.push_back({corners[0], corners[k - 1], corners[k]});
}

void check_vertex_count(std::size_t vertices, const std::string& name) {
  if (vertices > static_cast<std::size_t>(INT32_MAX))
    throw InputError(fmt::format("mesh file '{}' has more than 2^31 vertices: split or decimate it", name));
}

// ---------- STL ----------

float get_f32(const char* p) {
  float value;
  std::memcpy(&value, p, 4);  // STL is little-endian, as every machine poreshell builds for
  return value;
}

std::uint32_t get_u32(const char* p) {
  std::uint32_t value;
  std::memcpy(&value, p, 4);
  return value;
}

TriangleMesh read_stl_binary_bytes(std::string_view bytes, const std::string& name) {
  if (bytes.size() < kStlHeaderBytes + 4)
    throw InputError(fmt::format(
        "mesh file '{}' is not an STL file: it is {} bytes long, shorter than a binary STL's 84-byte header, "
        "and does not start with 'solid'; re-export it as STL",
        name, bytes.size()));
  const std::uint64_t count = get_u32(bytes.data() + kStlHeaderBytes);
  const std::uint64_t needed = kStlHeaderBytes + 4 + kStlFacetBytes * count;
  if (bytes.size() < needed)
    throw InputError(fmt::format(
        "mesh file '{}' is truncated: as a binary STL it declares {} triangles ({} bytes), but it holds {} "
        "bytes; re-export it",
        name, count, needed, bytes.size()));
  TriangleMesh mesh;
  check_vertex_count(3 * count, name);
  mesh.vertices.reserve(3 * count);
  mesh.triangles.reserve(count);
  for (std::size_t f = 0; f < count; ++f) {
    const char* facet = bytes.data() + kStlHeaderBytes + 4 + kStlFacetBytes * f;
    for (std::size_t c = 1; c <= 3; ++c)  // the facet normal (c = 0) is recomputed from the corners
      mesh.vertices.emplace_back(get_f32(facet + 12 * c), get_f32(facet + 12 * c + 4),
                                 get_f32(facet + 12 * c + 8));
    const auto v = static_cast<std::int32_t>(3 * f);
    mesh.triangles.push_back({v, v + 1, v + 2});
  }
  return mesh;
}

[[noreturn]] void bad_stl_line(const std::string& name, std::size_t line, const std::string& what) {
  throw InputError(
      fmt::format("ASCII STL file '{}', line {}: {}; the file is malformed, re-export it", name, line, what));
}

TriangleMesh read_stl_ascii_bytes(std::string_view bytes, const std::string& name) {
  TriangleMesh mesh;
  std::vector<std::int32_t> loop;
  bool in_loop = false;
  text::Lines lines(bytes);
  for (std::string_view line; lines.next(line);) {
    std::string_view rest = line;
    const std::string_view keyword = text::next_token(rest);
    if (keyword.empty() || equals_lower(keyword, "solid") || equals_lower(keyword, "endsolid") ||
        equals_lower(keyword, "facet") || equals_lower(keyword, "endfacet"))
      continue;  // names after solid and the facet normal are not needed
    if (equals_lower(keyword, "outer")) {
      if (in_loop) bad_stl_line(name, lines.number(), "a loop inside a loop");
      in_loop = true;
      loop.clear();
    } else if (equals_lower(keyword, "vertex")) {
      if (!in_loop) bad_stl_line(name, lines.number(), "a vertex outside 'outer loop'");
      Vec3 p;
      for (int a = 0; a < 3; ++a)
        if (!text::parse_double(text::next_token(rest), p[a]))
          bad_stl_line(name, lines.number(),
                       fmt::format("expected 'vertex x y z', got '{}'", text::quote(line, 60)));
      check_vertex_count(mesh.vertices.size() + 1, name);
      loop.push_back(static_cast<std::int32_t>(mesh.vertices.size()));
      mesh.vertices.push_back(p);
    } else if (equals_lower(keyword, "endloop")) {
      if (!in_loop) bad_stl_line(name, lines.number(), "'endloop' without 'outer loop'");
      // A facet is a triangle: more corners are not a polygon STL knows (issue 47: read as a quad).
      if (loop.size() != 3)
        bad_stl_line(name, lines.number(),
                     fmt::format("a facet with {} vertices (an STL facet has exactly 3)", loop.size()));
      append_fan(loop, mesh);
      in_loop = false;
    } else {
      bad_stl_line(name, lines.number(), fmt::format("unexpected '{}'", text::quote(keyword)));
    }
  }
  if (in_loop)
    throw InputError(
        fmt::format("ASCII STL file '{}' is truncated: it ends inside a facet; re-export it", name));
  return mesh;
}

// ASCII STL starts with "solid", but so do many binary files' headers: a file is binary when its size
// is exactly what its triangle count says, or when it holds bytes no text file has.
bool looks_like_ascii_stl(std::string_view bytes) {
  std::string_view head = bytes;
  if (!equals_lower(text::next_token(head), "solid")) return false;
  if (bytes.size() >= kStlHeaderBytes + 4 &&
      bytes.size() ==
          kStlHeaderBytes + 4 + kStlFacetBytes * std::uint64_t{get_u32(bytes.data() + kStlHeaderBytes)})
    return false;
  return std::none_of(bytes.begin(), bytes.end(), [](char ch) {
    const auto u = static_cast<unsigned char>(ch);
    return u < 0x20 && !text::is_space(ch);
  });
}

// ---------- OBJ ----------

[[noreturn]] void bad_line(const char* format, const std::string& name, std::size_t line,
                           const std::string& what) {
  throw InputError(fmt::format("{} file '{}', line {}: {}; the file is malformed, re-export it", format, name,
                               line, what));
}

// One corner of an OBJ face: "v", "v/vt", "v//vn" or "v/vt/vn"; negative v counts back from the last
// vertex read so far.
std::int32_t obj_corner(std::string_view token, std::size_t vertices, const std::string& name,
                        std::size_t line) {
  const std::string_view index = token.substr(0, token.find('/'));
  long long v = 0;
  const auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), v);
  if (ec != std::errc() || end != index.data() + index.size() || v == 0)
    bad_line("OBJ", name, line,
             fmt::format("'{}' is not a vertex index (1, 2, ... or -1, -2, ... counting back)",
                         text::quote(token)));
  const long long n = static_cast<long long>(vertices);
  const long long zero_based = v > 0 ? v - 1 : n + v;
  if (zero_based < 0 || zero_based >= n)
    bad_line("OBJ", name, line,
             fmt::format("the face refers to vertex {}, but only {} vertices come before it", v, vertices));
  return static_cast<std::int32_t>(zero_based);
}

// ---------- OFF ----------

// Strips a '#' comment.
std::string_view uncommented(std::string_view line) {
  return line.substr(0, line.find('#'));
}

bool next_content_line(text::Lines& lines, std::string_view& line) {
  while (lines.next(line)) {
    line = uncommented(line);
    std::string_view probe = line;
    if (!text::next_token(probe).empty()) return true;
  }
  return false;
}

std::size_t off_count(std::string_view token, const std::string& name, std::size_t line, const char* what) {
  long long n = -1;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), n);
  if (ec != std::errc() || end != token.data() + token.size() || n < 0 || n > INT32_MAX)
    bad_line("OFF", name, line,
             fmt::format("expected the {} count, a whole number from 0 to 2^31 - 1, got '{}'", what,
                         text::quote(token)));
  return static_cast<std::size_t>(n);
}

}  // namespace

TriangleMesh read_stl_bytes(std::string_view bytes, const std::string& name) {
  return looks_like_ascii_stl(bytes) ? read_stl_ascii_bytes(bytes, name) : read_stl_binary_bytes(bytes, name);
}

TriangleMesh read_obj_bytes(std::string_view bytes, const std::string& name) {
  TriangleMesh mesh;
  std::vector<std::int32_t> corners;
  text::Lines lines(bytes);
  for (std::string_view line; lines.next(line);) {
    // A NUL byte is binary data, not text: the line's keyword would be unknown and its face lost.
    if (line.find('\0') != std::string_view::npos)
      bad_line("OBJ", name, lines.number(), "a NUL byte (binary data in a text file)");
    std::string_view rest = line;
    const std::string_view keyword = text::next_token(rest);
    if (keyword == "v") {
      Vec3 p;
      for (int a = 0; a < 3; ++a)
        if (!text::parse_double(text::next_token(rest), p[a]))
          bad_line("OBJ", name, lines.number(),
                   fmt::format("expected 'v x y z', got '{}'", text::quote(line, 60)));
      check_vertex_count(mesh.vertices.size() + 1, name);
      mesh.vertices.push_back(p);  // a w or colour columns after x y z are ignored
    } else if (keyword == "f") {
      corners.clear();
      for (std::string_view token = text::next_token(rest); !token.empty(); token = text::next_token(rest))
        corners.push_back(obj_corner(token, mesh.vertices.size(), name, lines.number()));
      if (corners.size() < 3)
        bad_line("OBJ", name, lines.number(),
                 fmt::format("a face with {} vertices (3 or more needed)", corners.size()));
      append_fan(corners, mesh);
    }
    // Everything else (vt, vn, g, o, s, usemtl, mtllib, l, p, comments) carries no surface.
  }
  return mesh;
}

TriangleMesh read_off_bytes(std::string_view bytes, const std::string& name) {
  text::Lines lines(bytes);
  std::string_view line;
  if (!next_content_line(lines, line))
    throw InputError(
        fmt::format("OFF file '{}' holds no data (only blank or comment lines): re-export it", name));
  std::string_view rest = line;
  std::string_view token = text::next_token(rest);
  // The keyword is optional: [ST][C][N]OFF; 4OFF, nOFF and BINARY are other layouts.
  if (token.size() >= 3 && token.substr(token.size() - 3) == "OFF") {
    if (token.find_first_not_of("STCN", 0) != token.size() - 3)
      throw InputError(fmt::format(
          "OFF file '{}' is a '{}' file, which poreshell does not read: give a 3D 'OFF' (or COFF, NOFF) file",
          name, text::quote(token)));
    token = text::next_token(rest);
    if (equals_lower(token, "binary"))
      throw InputError(
          fmt::format("OFF file '{}' is binary, which poreshell does not read: save it as text OFF", name));
    if (token.empty()) {  // the counts are on the next line
      if (!next_content_line(lines, line))
        throw InputError(fmt::format("OFF file '{}' is truncated: it ends after its 'OFF' line", name));
      rest = line;
      token = text::next_token(rest);
    }
  }
  const std::size_t nv = off_count(token, name, lines.number(), "vertex");
  const std::size_t nf = off_count(text::next_token(rest), name, lines.number(), "face");
  // A vertex line takes 6 bytes at least ("0 0 0\n"), a face line 2: counts beyond the file's size are a
  // lie, refused before anything is reserved.
  if (6.0 * static_cast<double>(nv) + 2.0 * static_cast<double>(nf) > static_cast<double>(bytes.size()) + 1.0)
    throw InputError(fmt::format(
        "OFF file '{}' is truncated or its counts are wrong: it declares {} vertices and {} faces, more than "
        "its {} bytes can hold; re-export it",
        name, nv, nf, bytes.size()));
  TriangleMesh mesh;
  mesh.vertices.reserve(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    if (!next_content_line(lines, line))
      throw InputError(fmt::format(
          "OFF file '{}' is truncated: it declares {} vertices but holds {}; re-export it", name, nv, v));
    rest = line;
    Vec3 p;
    for (int a = 0; a < 3; ++a)
      if (!text::parse_double(text::next_token(rest), p[a]))
        bad_line("OFF", name, lines.number(),
                 fmt::format("expected vertex {} as 'x y z', got '{}'", v, text::quote(line, 60)));
    mesh.vertices.push_back(p);  // colours or normals after x y z are ignored
  }
  std::vector<std::int32_t> corners;
  for (std::size_t f = 0; f < nf; ++f) {
    if (!next_content_line(lines, line))
      throw InputError(fmt::format(
          "OFF file '{}' is truncated: it declares {} faces but holds {}; re-export it", name, nf, f));
    rest = line;
    const std::size_t n = off_count(text::next_token(rest), name, lines.number(), "face's vertex");
    corners.clear();
    for (std::size_t k = 0; k < n; ++k) {
      const std::string_view index = text::next_token(rest);
      long long i = -1;
      const auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), i);
      if (index.empty() || ec != std::errc() || end != index.data() + index.size())
        bad_line("OFF", name, lines.number(),
                 fmt::format("face {} lists {} vertices, but '{}' is not a vertex index", f, n,
                             text::quote(index)));
      if (i < 0 || i >= static_cast<long long>(nv))
        bad_line("OFF", name, lines.number(),
                 fmt::format("face {} refers to vertex {}, but the file has {} vertices (0 to {})", f, i, nv,
                             static_cast<long long>(nv) - 1));
      corners.push_back(static_cast<std::int32_t>(i));
    }
    append_fan(corners, mesh);  // faces of 1 or 2 vertices (points, lines) carry no surface
  }
  return mesh;
}

}  // namespace poreshell
