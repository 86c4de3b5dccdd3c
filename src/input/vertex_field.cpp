#include "input/vertex_field.hpp"

// The PLY file is read by io/ply_reader (vertices, the property, faces as fans); this file checks the
// values and builds the closest-point search.

#include <fmt/format.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <variant>

#include "core/error.hpp"
#include "core/units.hpp"
#include "geometry/mesh.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/point_tree.hpp"
#include "io/file_bytes.hpp"
#include "io/ply_reader.hpp"
#include "io/text_scan.hpp"

namespace poreshell {
namespace {

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
  const bool has_face = std::any_of(triangles_.begin(), triangles_.end(),
                                    [](const auto& t) { return !has_repeated_vertex(t); });
  if (has_face)
    surface_ = std::make_shared<const MeshSurface>(TriangleMesh{vertices_, triangles_});
  else
    points_ = std::make_shared<const PointTree>(vertices_);
}

VertexScalarField VertexScalarField::read_ply(const std::filesystem::path& path,
                                              const std::string& property) {
  return from_ply_bytes(read_file_bytes(path, "PLY"), path.string(), property);
}

VertexScalarField VertexScalarField::from_ply_bytes(std::string_view bytes, const std::string& name,
                                                    const std::string& property) {
  ply::Data ply = ply::read(bytes, name, property);
  for (std::size_t i = 0; i < ply.vertices.size(); ++i)
    if (!ply.vertices[i].allFinite() || !std::isfinite(ply.values[i]))
      throw InputError(fmt::format(
          "PLY file '{}': vertex {} (counting from 0) has a NaN or infinite {}; fix or repaint it", name, i,
          ply.vertices[i].allFinite() ? fmt::format("'{}'", text::quote(property))
                                      : std::string("coordinate")));
  return VertexScalarField(std::move(ply.vertices), std::move(ply.values), std::move(ply.triangles),
                           property);
}

std::vector<std::string> VertexScalarField::scalar_vertex_properties(const std::filesystem::path& path) {
  return ply::scalar_vertex_properties(read_file_bytes(path, "PLY"), path.string());
}

double VertexScalarField::at(const Vec3& p) const {
  if (surface_ == nullptr) return values_[points_->nearest(p).first];
  const MeshSurface::NearestTriangle nearest = surface_->nearest_triangle(p);
  return on_triangle(nearest.triangle, nearest.point);
}

double VertexScalarField::at_or(const Vec3& p, double reach, double outside) const {
  if (surface_ == nullptr) {
    const auto [vertex, distance] = points_->nearest(p);
    return distance <= reach ? values_[vertex] : outside;
  }
  const std::optional<MeshSurface::NearestTriangle> nearest = surface_->nearest_triangle_within(p, reach);
  return nearest ? on_triangle(nearest->triangle, nearest->point) : outside;
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
