#pragma once
// Where a surface cannot carry a hole: parts thinner than a hole (ears, fingers, claws, tails), where a
// hole would cut the part into a ring or a notch, and sharp creases, where a hole would straddle the
// edge as a D. Found on the input mesh (thin parts also on a point cloud), they become solid zones like
// rims (pattern/solid_zones.hpp), so the pattern arranges itself around them.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/mesh.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

struct SurfaceFeatures {
  std::vector<double> thin;                  // per mesh vertex: 1 on or near a thin part, else 0
  std::vector<std::array<Vec3, 2>> creases;  // sharp edges, in chains at least as long as a hole
  std::int64_t thin_vertices = 0;            // vertices marked (the margin included)
  std::int64_t crease_edges = 0;
};

struct FeatureOptions {
  double thin_below = 0.0;       // a part thinner than this is thin (the mesh's units); 0: off
  double margin = 0.0;           // vertices within this of a thin one are marked too
  double crease_degrees = 0.0;   // dihedral angle above which an edge is sharp; 0: off
  double min_crease_length = 0;  // shorter chains of sharp edges are scan noise, not creases
};

// `surface` answers distances to `mesh` (the same triangles). The thickness test, at the hole's scale: a
// ball of radius R = thin_below / 2 fits where, touching the surface at a vertex from inside (along the
// inward normal), it stays at distance t from the surface for t at 1/4, 1/2, 3/4 and 1 of R. A vertex is
// thin where no fitting ball's centre lies within R + margin of it: not where its own ball is short of
// room in a groove or on a bump of the scan, but where no ball of that size fits in the part nearby.
// Needs outward-oriented triangles (an inward mesh is turned by its signed volume).
SurfaceFeatures find_surface_features(const TriangleMesh& mesh, const Surface& surface,
                                      const FeatureOptions& options);

// A point cloud's normals turned to one side (Hoppe et al. 1992): along a tree of the 12-nearest-
// neighbour graph that bends least, each normal agrees with the one it is reached from; each part of
// the graph starts at its point of largest x, turned to +x, outward on a closed part.
std::vector<Vec3> oriented_normals(std::span<const Vec3> points, std::span<const Vec3> normals,
                                   const PointTree& tree);

// The thickness test on a point cloud, as on a mesh (above) with the normals oriented (outward, so the
// ball goes in along the other side), from depths of twice the point's spacing on (its neighbours'
// splats, tilted by their normals' noise, come closer than 0.9 t nearer it). 1 or 0 per point, grown by
// the margin. `spacing`: per point, the distance to its neighbours (the splats' radii); `tree`: over
// `points`, in their order (the caller keeps it for looking marks up).
std::vector<double> thin_points(std::span<const Vec3> points, std::span<const Vec3> normals,
                                std::span<const double> spacing, const PointTree& tree,
                                const Surface& surface, const FeatureOptions& options);

}  // namespace poreshell
