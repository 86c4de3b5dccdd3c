#pragma once
// A scalar painted on a mesh and saved as a PLY vertex property (`property float quality`, a hole
// scale, a 0/1 keep-out mask), evaluated anywhere near the surface: the solver asks at the closest
// points of grid voxels, so the value at p is the barycentric interpolation of the vertex values at
// the closest point of p on the file's own faces.
//
// Assimp drops custom PLY properties, so the file is read by io/ply_reader (ascii and both binary
// formats, any scalar type; polygons become fans). A file without faces (a painted point cloud) is allowed:
// the value at p is then that of the nearest vertex.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "poreshell/geometry.hpp"

namespace poreshell {

class MeshSurface;
class PointTree;

class VertexScalarField {
 public:
  // values[i] belongs to vertices[i]; triangles index vertices. Without a triangle of three distinct
  // vertices, values come from the nearest vertex. Throws InputError for NaN/inf coordinates or values
  // and for out-of-range indices.
  VertexScalarField(std::vector<Vec3> vertices, std::vector<double> values,
                    std::vector<std::array<std::int32_t, 3>> triangles, std::string name = "");

  // The vertex property `property` of a PLY file, with its vertices and faces. Throws InputError for a
  // missing, malformed or truncated file, a missing property (naming those the file has), NaN/inf
  // values and face indices out of range.
  static VertexScalarField read_ply(const std::filesystem::path& path, const std::string& property);
  // The same from the file's bytes (`name` in messages): what the fuzzer drives.
  static VertexScalarField from_ply_bytes(std::string_view bytes, const std::string& name,
                                          const std::string& property);
  // Names of the scalar vertex properties of a PLY file (x, y, z included), for choosing and messages.
  static std::vector<std::string> scalar_vertex_properties(const std::filesystem::path& path);

  // The value at the closest point of p on the faces (or at the nearest vertex, without faces). Safe to
  // call from many threads.
  double at(const Vec3& p) const;
  // at(p) where the faces (or, without faces, a vertex) come within `reach` of p, else `outside`: a
  // field painted on part of a surface, asked at points on the whole of it, in a search that stops at
  // reach.
  double at_or(const Vec3& p, double reach, double outside) const;

  // Maps the vertices into another frame (the pipeline's), so that at() takes points of that frame.
  // Values stay with their vertices; an affine map keeps the barycentric coordinates of every point.
  void transform(const std::function<Vec3(const Vec3&)>& to_frame);

  std::pair<double, double> range() const { return range_; }  // min, max of the vertex values
  std::size_t vertex_count() const { return vertices_.size(); }
  std::size_t triangle_count() const { return triangles_.size(); }
  bool interpolates_on_faces() const { return surface_ != nullptr; }
  const std::string& name() const { return name_; }

 private:
  void build_search();  // the closest-point structure over the current vertices
  double on_triangle(std::size_t triangle, const Vec3& q) const;

  std::vector<Vec3> vertices_;
  std::vector<double> values_;
  std::vector<std::array<std::int32_t, 3>> triangles_;
  std::string name_;
  std::pair<double, double> range_{0.0, 0.0};
  // Shared and read-only, so that copies of a field are cheap; transform() builds new ones.
  std::shared_ptr<const MeshSurface> surface_;  // with faces
  std::shared_ptr<const PointTree> points_;     // without faces
};

// The vertex field `name` of a mesh input (MeshInput::vertex_fields) as a function of a point in mm,
// interpolated on the input's faces. Throws OptionError naming `option` when there is no such field.
std::function<double(const Vec3&)> input_vertex_field(const Input& input, const std::string& name,
                                                      const std::string& option);

}  // namespace poreshell
