#pragma once
// Creases of a max of parts inside the isosurface's tetrahedra. Each part is affine in a tetrahedron
// (from its values at the four corners), so the solid {every part < iso} is the tetrahedron cut by
// planes, and its surface is one flat piece per part, the pieces meeting on straight creases. Marching
// tetrahedra join the vertices on the tetrahedron's edges by one triangle or quad across a crease, a
// chamfer up to half a cell deep. Here, between two consecutive vertices of that patch that lie on two
// parts' faces, the crease's end on the tetrahedron's face between them is a vertex too (and, where
// three parts meet, their common point inside), and the patch is split along the crease. A crease's
// end depends on its face's three corners alone, so the two tetrahedra beside a face insert the same
// point between the same two vertices: the mesh stays closed and manifold.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/types.hpp"

namespace poreshell {

inline constexpr std::size_t kMaxTetParts = 3;
inline constexpr std::uint8_t kOnCrease = 255;

// A corner of a patch: its position (in any frame, to choose the triangles' shapes) and the part whose
// face it lies on, or kOnCrease.
struct PatchCorner {
  Vec3 position = Vec3::Zero();
  std::uint8_t part = 0;
};

// Triangles of a convex patch given counter-clockwise whose corners include its crease points, split
// along them: with two crease points into the two parts' pieces, with three into three pieces meeting
// at `inside` (index corners.size()) if given, otherwise fanned whole. Indices into `corners`,
// counter-clockwise.
void split_at_creases(std::span<const PatchCorner> corners, const Vec3* inside,
                      std::vector<std::array<int, 3>>& out);

// Where parts i and j are both at iso on a triangle (values[k][c]: part k at its corner c): barycentric
// weights, or none where one is under `snap` (the isosurface keeps its vertices that far off an edge's
// ends). Where the crease misses the triangle, the solid pokes through its third side between two corners
// outside, which marching tetrahedra do not see: that chamfer stays.
std::optional<std::array<double, 3>> face_crease_weights(std::span<const std::array<double, 3>> values,
                                                         std::size_t i, std::size_t j, double iso,
                                                         double snap);

// Where parts 0, 1 and 2 are all at iso in a tetrahedron: barycentric weights of its corners, or none
// where one is under `snap`.
std::optional<std::array<double, 4>> inside_crease_weights(std::span<const std::array<double, 4>> values,
                                                           double iso, double snap);

}  // namespace poreshell
