#pragma once
// What a run takes: a triangle mesh or a point cloud in memory (in a stated unit), or one of the
// paper's analytic shapes. Plain arrays, so that callers need none of the library's dependencies.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>
#include "poreshell/export.hpp"

namespace poreshell {

using Point = std::array<double, 3>;
using Triangle = std::array<std::int32_t, 3>;  // vertex indices, counter-clockwise seen from outside

struct Mesh {
  std::vector<Point> vertices;
  std::vector<Triangle> triangles;
};

enum class Unit { m, cm, mm, inch };

// A triangle mesh (a scan with holes, an open surface). `vertex_fields` are scalars per vertex (same
// order as `mesh.vertices`) that options may name: `keep_out_mask`, a grading field.
struct MeshInput {
  Mesh mesh;
  Unit unit = Unit::mm;
  std::string name = "mesh";  // for the report: a file name, a part name
  std::map<std::string, std::vector<double>> vertex_fields;
  // Triangles load_mesh dropped from the file (zero area or a repeated vertex; repeats of a triangle),
  // which the report counts with those the run drops.
  std::int64_t dropped_degenerate = 0, dropped_duplicate = 0;
};

// A point cloud; `patches` are optional triangles over the points (the paper's route densifies them).
struct PointsInput {
  std::vector<Point> points;
  std::vector<Triangle> patches;
  Unit unit = Unit::mm;
  std::string name = "points";
};

// The paper's analytic surfaces: the sphere of eq. (3.1) and the torus of section 3.2, in the unit
// cube, or at a size in millimetres (the sphere's radius, the torus's major radius).
enum class ShapeKind { sphere, torus };
struct ShapeInput {
  ShapeKind kind = ShapeKind::sphere;
  double radius_mm = 0.0;  // 0: the paper's unit cube (then `unit` says what one unit is)
  Unit unit = Unit::mm;
};

using Input = std::variant<ShapeInput, MeshInput, PointsInput>;

inline ShapeInput sphere(double radius_mm = 0.0) {
  return {ShapeKind::sphere, radius_mm, Unit::mm};
}
inline ShapeInput torus(double major_radius_mm = 0.0) {
  return {ShapeKind::torus, major_radius_mm, Unit::mm};
}

// Millimetres per unit, and the unit's name ("m", "cm", "mm", "inch").
PORESHELL_API double millimetres_per(Unit unit);
PORESHELL_API const char* to_string(Unit unit);
// The unit whose name to_string() gives, or none.
PORESHELL_API std::optional<Unit> unit_from_name(std::string_view name);

}  // namespace poreshell
