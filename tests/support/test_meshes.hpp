#pragma once
// Meshes several tests build, as the public API's Mesh (outward, counter-clockwise seen from outside),
// and their copy into the library's TriangleMesh. Vertices are computed as radius times a unit
// direction, so a test that shifts a mesh (append with a centre) gets the bits it computed before.

#include <array>
#include <filesystem>
#include <vector>

#include "core/types.hpp"
#include "geometry/mesh.hpp"
#include "poreshell/geometry.hpp"

namespace poreshell::test_support {

// An open cylinder (a sleeve, no caps) about the z axis from z = 0 to `length`, normals outward:
// `segments` around and `rings` bands along, two boundary circles.
Mesh open_sleeve(double radius, double length, int segments = 96, int rings = 40);

// A closed surface of revolution about z from a profile of (rho, z) that starts and ends on the axis,
// outward when the profile runs from bottom to top.
Mesh revolve(const std::vector<std::array<double, 2>>& profile, int segments);

// A closed UV sphere of radius r about the origin: the poles, `rings` - 1 rings of `segments` vertices.
Mesh uv_sphere(double r, int rings, int segments);

// The upper half of a sphere of radius r about the origin, open along the equator: the north pole and
// `rings` rings of `segments` vertices, the last exactly on z = 0, so the boundary is a clean circle.
Mesh upper_hemisphere(double r, int rings, int segments);

// A flat square sheet [lo, lo + side]^2 in the plane z, normal +z: n x n squares, two triangles each.
Mesh square_sheet(double lo, double side, int n, double z = 0.0);

// A sphere from the icosahedron (outward counter-clockwise faces), each subdivision splitting a
// triangle into four and projecting the new vertices onto the sphere: 20 * 4^subdivisions triangles
// of nearly equal size, about `center`.
TriangleMesh icosphere(int subdivisions, const Vec3& center, double radius);

// The same mesh with every triangle turned over (normals inward).
Mesh inverted(Mesh mesh);

// Appends `mesh`, moved by `shift`, to `to`.
void append(TriangleMesh& to, const Mesh& mesh, const Vec3& shift = Vec3::Zero());
// `mesh` moved by `shift` as a TriangleMesh.
TriangleMesh to_triangle_mesh(const Mesh& mesh, const Vec3& shift = Vec3::Zero());

// Writes `mesh` as OBJ text, numbers as a default ostream prints them (six significant digits).
void write_obj_text(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace poreshell::test_support
