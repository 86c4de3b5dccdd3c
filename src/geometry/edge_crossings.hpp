#pragma once
// Where the isosurface crosses a grid edge (isosurface.cpp). Crossing parameters are clamped to
// [kSnap, 1 - kSnap] of the edge. On a shell of 589,448 triangles, kSnap = 0.001 left 7,520 triangles
// with an angle under 1 degree (302 under 0.1); 0.05 leaves none (smallest 1.4 degrees) and moves the
// surface by at most 0.05 of an edge; 0.15 left none under 5 degrees but moved a 3-cell wall's faces by
// 5% of its thickness.
//
// A clamped vertex is then moved within its edge's neighbourhood onto the plane through its exact crossing,
// normal to the field's gradient at the grid point it came near: along the surface, not off it. Left on
// its edge it stood up to 0.05 of an edge (0.033 mm on a 0.67 mm shell grid) off a flat face, alternately
// above and below along every curve where the face passes near grid points; bumps larger than a 0.02 mm
// reduction bound, which the reduction then had to keep (sphere r 50 mm, `--lean`: 255,108 triangles,
// 202,122 with the move; docs/benchmarks.md, "What keeps the faces fine"). Where a move makes a triangle
// with an angle under kLeastAngleDegrees or turns one over, its moved vertices go back to their clamped
// places; the clamped places make neither, so this ends.

#include <cstdint>
#include <span>
#include <vector>

#include "geometry/kuhn_grid.hpp"
#include "geometry/mesh.hpp"

namespace poreshell::kuhn {

constexpr double kSnap = 0.05;  // in units of the edge length
// No triangle of the output is finer than this; tests and the reduction hold 1 degree, with a margin.
constexpr double kLeastAngleDegrees = 1.2;

// Crossing parameter from the edge's lower end; exactly one of va, vb is below iso.
double crossing(double va, double vb, double iso);

// The same for the max of parts, each linear along the edge, at points i (lower end) and j: the inside,
// where every part is below iso, is the overlap of the parts' insides, an interval at the inside end;
// the crossing is its other end, clamped as crossing() does. `part`, if given, receives which part crosses
// there; `exact`, the crossing before the clamp.
double crossing_of_max(std::span<const std::span<const double>> parts, std::size_t i, std::size_t j,
                       double iso, std::uint8_t* part = nullptr, double* exact = nullptr);

// The unit steps of a cube's corner mask (bit 0: +x, bit 1: +y, bit 2: +z).
inline Vec3 direction(int bits) {
  return Vec3(bits & 1, (bits >> 1) & 1, (bits >> 2) & 1);
}

struct EdgeCrossing {
  double t;      // clamped to [kSnap, 1 - kSnap]
  double exact;  // in [0, 1]
};

// The crossing on the edge from point key `lower` to `upper` (of the max of the parts where there are).
EdgeCrossing vertex_crossing(const FieldLookup& lookup, std::int64_t lower, std::int64_t upper, double iso);

// Where a clamped crossing goes (grid index units): onto the plane through the exact crossing, normal to
// the field's gradient (central differences) at the grid point it came near. `at` where the gradient
// vanishes.
Vec3 along_surface(const FieldLookup& lookup, const PaddedGrid& grid, std::int64_t lower, int bits,
                   const EdgeCrossing& c, const Vec3& at);

// The clamped crossings that along_surface() moved: their vertices (ascending) and clamped places.
struct MovedCrossings {
  std::vector<char> moved;             // per vertex
  std::vector<std::int32_t> vertices;  // those moved, ascending
  std::vector<Vec3> clamped;           // their clamped places, in the same order

  const Vec3& clamped_place(const TriangleMesh& mesh, std::size_t v) const;
};

// Puts the moved vertices of a triangle back at their clamped places where the move makes the triangle
// finer than kLeastAngleDegrees or turns it over, until no such triangle is left (the clamped places make
// none, so this ends). Each round decides from the positions it starts with: the same result for any
// thread count.
void undo_moves_that_spoil_triangles(TriangleMesh& mesh, MovedCrossings& m);

}  // namespace poreshell::kuhn
