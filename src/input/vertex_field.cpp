#include "input/vertex_field.hpp"

// The PLY body is read into memory and walked row by row, element by element, through a cursor that
// reads one value of a given type (text tokens or binary, either byte order). Only the vertex and face
// elements are kept; other elements are read through and dropped, since binary rows have no markers to
// skip by. ASCII data is read as a stream of tokens, not line by line, as other PLY readers do.

#include <fmt/format.h>
#include <fmt/ranges.h>  // join

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <variant>

#include "core/error.hpp"
#include "core/units.hpp"
#include "geometry/mesh.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/point_tree.hpp"
#include "io/ply_header.hpp"

namespace poreshell {
namespace {

using ply::ScalarType;

// Thrown while reading rows; read_body turns them into InputErrors that say where the data went wrong.
struct EndOfData {};
struct BadValue {
  std::string what;
};

class AsciiCursor {
 public:
  // `end` must point at a '\0' (std::string data does), which stops strtod.
  AsciiCursor(const char* begin, const char* end) : p_(begin), end_(end) {}

  // strtod also reads "nan" and "inf", so those are reported as such rather than as unreadable.
  double read(ScalarType /*type*/) {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\n' || *p_ == '\r')) ++p_;
    if (p_ == end_) throw EndOfData{};
    char* after = nullptr;
    const double value = std::strtod(p_, &after);
    if (after == p_ || (after < end_ && !std::isspace(static_cast<unsigned char>(*after)))) {
      const char* token_end =
          std::find_if(p_, end_, [](char ch) { return std::isspace(static_cast<unsigned char>(ch)) != 0; });
      const std::string token(p_, std::min<std::size_t>(static_cast<std::size_t>(token_end - p_), 40));
      throw BadValue{fmt::format("'{}' is not a number", token)};
    }
    p_ = after;
    return value;
  }

 private:
  const char* p_;
  const char* end_;
};

class BinaryCursor {
 public:
  BinaryCursor(const char* begin, const char* end, bool big_endian)
      : p_(begin), end_(end), swap_(big_endian != (std::endian::native == std::endian::big)) {}

  double read(ScalarType type) {
    const std::size_t n = ply::scalar_bytes(type);
    if (static_cast<std::size_t>(end_ - p_) < n) throw EndOfData{};
    unsigned char bytes[8];
    std::memcpy(bytes, p_, n);
    p_ += n;
    if (swap_) std::reverse(bytes, bytes + n);
    switch (type) {
      case ScalarType::int8:
        return as<std::int8_t>(bytes);
      case ScalarType::uint8:
        return as<std::uint8_t>(bytes);
      case ScalarType::int16:
        return as<std::int16_t>(bytes);
      case ScalarType::uint16:
        return as<std::uint16_t>(bytes);
      case ScalarType::int32:
        return as<std::int32_t>(bytes);
      case ScalarType::uint32:
        return as<std::uint32_t>(bytes);
      case ScalarType::float32:
        return as<float>(bytes);
      case ScalarType::float64:
        return as<double>(bytes);
    }
    return 0.0;
  }

 private:
  template <class T>
  static double as(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof value);
    return static_cast<double>(value);
  }

  const char* p_;
  const char* end_;
  bool swap_;
};

// Where the wanted properties sit in the rows of the vertex and face elements.
struct Layout {
  const ply::Element* vertex = nullptr;
  const ply::Element* face = nullptr;  // null without faces
  std::array<std::size_t, 3> xyz{};    // property positions in a vertex row
  std::size_t value = 0;               // position of the field's property in a vertex row
  std::size_t indices = 0;             // position of the vertex index list in a face row
};

struct PlyData {
  std::vector<Vec3> vertices;
  std::vector<double> values;
  std::vector<std::array<std::int32_t, 3>> triangles;
};

std::optional<std::size_t> position(const ply::Element& element, const std::string& name) {
  for (std::size_t k = 0; k < element.properties.size(); ++k)
    if (element.properties[k].name == name && !element.properties[k].is_list) return k;
  return std::nullopt;
}

std::vector<std::string> scalar_names(const ply::Element& element) {
  std::vector<std::string> names;
  for (const ply::Property& p : element.properties)
    if (!p.is_list) names.push_back(p.name);
  return names;
}

// Hints where the property is, when the file has it on another element (per-face quality, say).
std::string elsewhere(const ply::Header& header, const std::string& property) {
  for (const ply::Element& e : header.elements)
    if (e.name != "vertex" && e.find(property) != nullptr)
      return fmt::format(" (the file has it on its '{}' elements: transfer it to the vertices)", e.name);
  return "";
}

Layout find_layout(const ply::Header& header, const std::filesystem::path& path,
                   const std::string& property) {
  Layout layout;
  layout.vertex = header.find("vertex");
  if (layout.vertex == nullptr || layout.vertex->count == 0)
    throw InputError(fmt::format(
        "PLY file '{}' has no vertices: a vertex field needs the painted mesh's vertices", path.string()));
  for (int a = 0; a < 3; ++a) {
    const std::string axis(1, static_cast<char>('x' + a));
    const auto k = position(*layout.vertex, axis);
    if (!k)
      throw InputError(
          fmt::format("PLY file '{}': its vertices have no scalar '{}' coordinate; re-export the mesh",
                      path.string(), axis));
    layout.xyz[a] = *k;
  }
  const auto value = position(*layout.vertex, property);
  if (!value)
    throw InputError(fmt::format(
        "PLY file '{}' has no scalar vertex property '{}'{}; its scalar vertex properties are: {}. Save the "
        "field as a per-vertex property or name one of these",
        path.string(), property, elsewhere(header, property), fmt::join(scalar_names(*layout.vertex), ", ")));
  layout.value = *value;
  layout.face = header.find("face");
  if (layout.face == nullptr || layout.face->count == 0) {
    layout.face = nullptr;
    return layout;
  }
  for (std::size_t k = 0; k < layout.face->properties.size(); ++k) {
    const ply::Property& p = layout.face->properties[k];
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
      layout.indices = k;
      return layout;
    }
  }
  throw InputError(fmt::format(
      "PLY file '{}': its faces have no 'vertex_indices' list, so they cannot be read; re-export the mesh",
      path.string()));
}

template <class Cursor>
std::size_t read_count(Cursor& cursor, ScalarType type) {
  const double n = cursor.read(type);
  if (!(n >= 0.0 && n <= INT32_MAX && n == std::floor(n)))
    throw BadValue{fmt::format("the list length {} is not a count", n)};
  return static_cast<std::size_t>(n);
}

// Reads a property and drops it.
template <class Cursor>
void skip(Cursor& cursor, const ply::Property& p) {
  const std::size_t n = p.is_list ? read_count(cursor, p.count_type) : 1;
  for (std::size_t i = 0; i < n; ++i) cursor.read(p.type);
}

template <class Cursor>
void read_vertex(Cursor& cursor, const Layout& layout, std::size_t row, const std::filesystem::path& path,
                 PlyData& out) {
  Vec3 p = Vec3::Zero();
  double value = 0.0;
  const auto& properties = layout.vertex->properties;
  for (std::size_t k = 0; k < properties.size(); ++k) {
    if (properties[k].is_list) {
      skip(cursor, properties[k]);
      continue;
    }
    const double v = cursor.read(properties[k].type);
    for (int a = 0; a < 3; ++a)
      if (k == layout.xyz[a]) p[a] = v;
    if (k == layout.value) value = v;
  }
  if (!p.allFinite() || !std::isfinite(value))
    throw InputError(fmt::format(
        "PLY file '{}': vertex {} (counting from 0) has a NaN or infinite {}; fix or repaint it",
        path.string(), row,
        p.allFinite() ? fmt::format("'{}'", properties[layout.value].name) : std::string("coordinate")));
  out.vertices.push_back(p);
  out.values.push_back(value);
}

template <class Cursor>
void read_face(Cursor& cursor, const Layout& layout, std::size_t row, const std::filesystem::path& path,
               PlyData& out) {
  const auto& properties = layout.face->properties;
  for (std::size_t k = 0; k < properties.size(); ++k) {
    if (k != layout.indices) {
      skip(cursor, properties[k]);
      continue;
    }
    const std::size_t n = read_count(cursor, properties[k].count_type);
    std::array<std::int32_t, 3> fan{};  // first, previous, current: a polygon becomes a fan
    for (std::size_t i = 0; i < n; ++i) {
      const double index = cursor.read(properties[k].type);
      const double vertices = static_cast<double>(layout.vertex->count);
      if (!(index >= 0.0 && index < vertices && index == std::floor(index)))
        throw InputError(fmt::format(
            "PLY file '{}': face {} (counting from 0) refers to vertex {}, but the file has {} vertices "
            "(0 to {}); the file is corrupt, re-export it",
            path.string(), row, index, layout.vertex->count, layout.vertex->count - 1));
      fan[std::min<std::size_t>(i, 2)] = static_cast<std::int32_t>(index);
      if (i >= 2) {
        out.triangles.push_back(fan);
        fan[1] = fan[2];
      }
    }
  }
}

// Reads the elements in file order up to the last one needed.
template <class Cursor>
PlyData read_body(Cursor& cursor, const ply::Header& header, const Layout& layout,
                  const std::filesystem::path& path) {
  PlyData out;
  out.vertices.reserve(layout.vertex->count);
  out.values.reserve(layout.vertex->count);
  std::size_t needed = layout.face != nullptr ? 2 : 1;
  for (const ply::Element& element : header.elements) {
    if (needed == 0) break;
    const bool is_vertex = &element == layout.vertex, is_face = &element == layout.face;
    std::size_t row = 0;
    try {
      for (; row < element.count; ++row) {
        if (is_vertex)
          read_vertex(cursor, layout, row, path, out);
        else if (is_face)
          read_face(cursor, layout, row, path, out);
        else
          for (const ply::Property& p : element.properties) skip(cursor, p);
      }
    } catch (const EndOfData&) {
      throw InputError(fmt::format(
          "PLY file '{}' is truncated: its header promises {} '{}' entries, the data ends in entry {} "
          "(counting from 0); re-export the file",
          path.string(), element.count, element.name, row));
    } catch (const BadValue& bad) {
      throw InputError(
          fmt::format("PLY file '{}', '{}' entry {} (counting from 0): {}; the data is malformed, "
                      "re-export the file",
                      path.string(), element.name, row, bad.what));
    }
    if (is_vertex || is_face) --needed;
  }
  return out;
}

ply::Header read_header_of(const std::filesystem::path& path, std::ifstream& in) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(
        fmt::format("PLY file '{}' does not exist or is not a file: check the path", path.string()));
  in.open(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("cannot open PLY file '{}': check its permissions", path.string()));
  return ply::read_header(in, path);
}

std::string rest_of(std::ifstream& in) {
  in.clear();  // a header without data ends at end of file, which tellg would report as a failure
  const std::streampos start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg() - start;
  in.seekg(start);
  std::string data(static_cast<std::size_t>(std::max<std::streamoff>(size, 0)), '\0');
  in.read(data.data(), static_cast<std::streamsize>(data.size()));
  data.resize(static_cast<std::size_t>(in.gcount()));
  return data;
}

// Along the nearest edge: a zero-area triangle is the union of its edges, and q lies on one of them.
double on_edges(const Vec3& q, const std::array<Vec3, 3>& x, const std::array<double, 3>& f) {
  double best_d2 = std::numeric_limits<double>::infinity(), best = f[0];
  for (int e = 0; e < 3; ++e) {
    const int a = e, b = (e + 1) % 3;
    const Vec3 ab = x[b] - x[a];
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((q - x[a]).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double d2 = (x[a] + t * ab - q).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = f[a] + t * (f[b] - f[a]);
    }
  }
  return best;
}

}  // namespace

VertexScalarField::VertexScalarField(std::vector<Vec3> vertices, std::vector<double> values,
                                     std::vector<std::array<std::int32_t, 3>> triangles, std::string name)
    : vertices_(std::move(vertices)),
      values_(std::move(values)),
      triangles_(std::move(triangles)),
      name_(std::move(name)) {
  if (values_.size() != vertices_.size())
    throw std::invalid_argument("VertexScalarField: one value per vertex is needed");
  if (vertices_.empty()) throw InputError("the vertex field has no vertices");
  for (std::size_t i = 0; i < values_.size(); ++i)
    if (!std::isfinite(values_[i]))
      throw InputError(fmt::format("the vertex field's value at vertex {} is NaN or infinite", i));
  for (const auto& t : triangles_)
    for (std::int32_t v : t)
      if (v < 0 || static_cast<std::size_t>(v) >= vertices_.size())
        throw InputError(
            fmt::format("a triangle of the vertex field refers to vertex {} of {}", v, vertices_.size()));
  const auto [lo, hi] = std::minmax_element(values_.begin(), values_.end());
  range_ = {*lo, *hi};
  build_search();
}

void VertexScalarField::build_search() {
  for (std::size_t i = 0; i < vertices_.size(); ++i)
    if (!vertices_[i].allFinite())
      throw InputError(fmt::format("vertex {} of the vertex field has a NaN or infinite coordinate", i));
  surface_.reset();
  points_.reset();
  // MeshSurface skips triangles with a repeated vertex; if that leaves none, the field is a point set.
  const bool has_face = std::any_of(triangles_.begin(), triangles_.end(), [](const auto& t) {
    return t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
  });
  if (has_face)
    surface_ = std::make_shared<const MeshSurface>(TriangleMesh{vertices_, triangles_});
  else
    points_ = std::make_shared<const PointTree>(vertices_);
}

VertexScalarField VertexScalarField::read_ply(const std::filesystem::path& path,
                                              const std::string& property) {
  std::ifstream in;
  const ply::Header header = read_header_of(path, in);
  const Layout layout = find_layout(header, path, property);
  const std::string data = rest_of(in);
  const char* begin = data.data();
  const char* end = begin + data.size();
  PlyData ply;
  if (header.format == ply::Format::ascii) {
    AsciiCursor cursor(begin, end);
    ply = read_body(cursor, header, layout, path);
  } else {
    BinaryCursor cursor(begin, end, header.format == ply::Format::binary_big_endian);
    ply = read_body(cursor, header, layout, path);
  }
  return VertexScalarField(std::move(ply.vertices), std::move(ply.values), std::move(ply.triangles),
                           property);
}

std::vector<std::string> VertexScalarField::scalar_vertex_properties(const std::filesystem::path& path) {
  std::ifstream in;
  const ply::Header header = read_header_of(path, in);
  const ply::Element* vertex = header.find("vertex");
  return vertex != nullptr ? scalar_names(*vertex) : std::vector<std::string>{};
}

double VertexScalarField::at(const Vec3& p) const {
  if (surface_ == nullptr) return values_[points_->nearest(p).first];
  const MeshSurface::NearestTriangle nearest = surface_->nearest_triangle(p);
  return on_triangle(nearest.triangle, nearest.point);
}

double VertexScalarField::on_triangle(std::size_t triangle, const Vec3& q) const {
  const auto& t = triangles_[triangle];
  const std::array<Vec3, 3> x{vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]};
  const std::array<double, 3> f{values_[t[0]], values_[t[1]], values_[t[2]]};
  if (classify_triangle(x[0], x[1], x[2]) != TriangleShape::degenerate) {
    // Barycentric weights as sub-triangle areas over the area, signed by the normal. q is on the
    // triangle, so negative weights are round-off: clamped, and the rest renormalised.
    const Vec3 n = (x[1] - x[0]).cross(x[2] - x[0]);
    const double inv = 1.0 / n.squaredNorm();
    std::array<double, 3> w{};
    for (int k = 0; k < 3; ++k)
      w[k] = std::max(0.0, n.dot((x[(k + 1) % 3] - q).cross(x[(k + 2) % 3] - q)) * inv);
    // Normalised weight by weight, so that at a vertex they are exactly (1, 0, 0) and give its value.
    const double sum = w[0] + w[1] + w[2];
    if (sum > 0.5 && std::isfinite(sum))
      return (w[0] / sum) * f[0] + (w[1] / sum) * f[1] + (w[2] / sum) * f[2];
  }
  return on_edges(q, x, f);
}

void VertexScalarField::transform(const std::function<Vec3(const Vec3&)>& to_frame) {
  for (Vec3& v : vertices_) v = to_frame(v);
  build_search();
}

std::function<double(const Vec3&)> input_vertex_field(const Input& input, const std::string& name,
                                                      const std::string& option) {
  const auto* mesh = std::get_if<MeshInput>(&input);
  const auto found = mesh ? mesh->vertex_fields.find(name) : decltype(mesh->vertex_fields.end()){};
  if (!mesh || found == mesh->vertex_fields.end())
    throw OptionError(option, "`" + option + "` reads the vertex field '" + name +
                                  "' of the input mesh, which has none of that name: give the mesh as a PLY "
                                  "file with a '" +
                                  name + "' vertex property, or the values per vertex");
  if (found->second.size() != mesh->mesh.vertices.size())
    throw InputError("the vertex field '" + name + "' has " + std::to_string(found->second.size()) +
                     " values for " + std::to_string(mesh->mesh.vertices.size()) +
                     " vertices: give one per vertex");
  std::vector<Vec3> vertices;
  vertices.reserve(mesh->mesh.vertices.size());
  for (const Point& p : mesh->mesh.vertices) vertices.emplace_back(p[0], p[1], p[2]);
  auto field = std::make_shared<const VertexScalarField>(
      std::move(vertices), found->second,
      std::vector<std::array<std::int32_t, 3>>(mesh->mesh.triangles.begin(), mesh->mesh.triangles.end()),
      name);
  const double mm_per_unit = millimetres_per(mesh->unit);
  return [field, mm_per_unit](const Vec3& x_mm) { return field->at(x_mm / mm_per_unit); };
}

}  // namespace poreshell
