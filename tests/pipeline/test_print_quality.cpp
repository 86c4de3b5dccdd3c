// Print quality through the public API (issue 19, items 1 and 2): what a cast maker would reject.
// 6 mm holes at 10 mm in a 2 mm wall (8 mm at 12 mm on the sleeve), default options.
//
// - A sphere (r 30 mm) with a thin stalk (r 3 mm, 30 mm long, capped) comes out as one part with the
//   whole stalk, no hole on the stalk nor reaching it (the nearest centre 9.4 mm from its foot), every
//   hole round and whole, and the sphere's holes as dense as on a bare sphere (105 against 105.9).
//   With thin_feature_ratio = 0 the stalk carries 4 holes; with both zones off 6, one 2.1 mm above its
//   foot, and the worst hole measures 4.10 mm and circularity 0.81. crease_angle = 0 alone passes (the
//   thin zone covers the foot too).
// - A cube (side 60 mm, edges and corners rounded with r 2 mm in two facets per quarter circle, so that
//   each edge has a 45 degree crease) has no hole within half a hole of an edge line, and the holes fill
//   what the zones leave at the bare sphere's density. With the defaults the nearest hole centre is
//   11.8 mm from an edge line (112 holes), with the crease zone alone 9.1 mm (138 holes); with both
//   zones off 0.9 mm, 32 of the 197 holes within half a hole of an edge (the hole table still finds
//   them round: least circularity 0.92 on a 2 mm round, so only their place gives them away).
// - An open sleeve (r 35 mm, 100 mm long, 8 mm holes at 12 mm, 3 mm rim) comes out as one part (it has
//   nothing to remove: no fragment, no void, with or without the clean-up).
//
// The hexagonal estimate: n holes at nearest-neighbour spacing s cover n sqrt(3)/2 s^2 in a perfect
// lattice. The hole map's spacing is the equation's mean nearest-neighbour distance (docs/printing.md,
// "the hole map"), and the equation's layout is no perfect lattice: an irregular layout with the same
// mean nearest-neighbour distance holds fewer holes, so a bare sphere has fewer than the lattice of
// that spacing: 107 on r 30 mm against 130.6, a density factor of 0.819 (before the even layout
// started from discs, 106 and 0.812 with both layouts). Each test measures that factor on the bare sphere
// with the same options (2 s), so that a change of layout moves the reference with the count, and asks for
// the count on the free surface within 10% of factor x the lattice estimate.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <vector>

#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

constexpr double kHole = 6.0, kSpacing = 10.0, kWall = 2.0;

Options holes_options() {
  Options o;
  o.hole_diameter = kHole;
  o.spacing = kSpacing;
  o.wall = kWall;
  return o;
}

// Holes of a perfect hexagonal lattice of this spacing on this area.
double lattice_estimate(double area_mm2, double spacing) {
  return area_mm2 / (std::sqrt(3.0) / 2 * spacing * spacing);
}

// The equation's holes over the lattice's on a bare sphere of radius 30 mm with the same options.
double density_factor(const Options& options) {
  constexpr double kRadius = 30.0;
  const Result r = perforate(sphere(kRadius), options);
  const double factor = static_cast<double>(r.outputs.at(0).holes.size()) /
                        lattice_estimate(4 * std::numbers::pi * kRadius * kRadius, options.spacing);
  std::printf("bare sphere r %.0f: %zu holes, density factor %.3f\n", kRadius, r.outputs[0].holes.size(),
              factor);
  // A layout denser than the lattice or a third emptier than today's would be news of its own.
  EXPECT_GT(factor, 0.7);
  EXPECT_LT(factor, 1.05);
  return factor;
}

// One part, no sealed void: the output is one connected solid (a kept cavity would be a second
// component), oriented outward.
void expect_one_part(const Result& r, const char* what) {
  ASSERT_EQ(r.outputs.size(), 1u);
  const LevelReport& level = r.report.outputs.at(0);
  EXPECT_EQ(level.parts.parts, 1) << what;
  EXPECT_EQ(level.topology.components, 1) << what;
  EXPECT_TRUE(level.topology.closed && level.topology.manifold && level.topology.oriented) << what;
  EXPECT_GT(level.topology.volume, 0.0) << what;
  std::printf("%s: %lld part(s); removed %lld fragment(s) and %lld void(s), %.3f mm^3; %zu holes\n", what,
              static_cast<long long>(level.parts.parts),
              static_cast<long long>(level.parts.removed_fragments),
              static_cast<long long>(level.parts.removed_voids), level.parts.removed_volume,
              r.outputs[0].holes.size());
}

// Round and whole: no slit, notch or fragment. Issue 19's bound is on the axis ratio (0.6; a half disc
// has 0.53); circularity, 0.87 by default, also refuses ragged loops (a half disc measures 0.75).
void expect_round_whole_holes(const std::vector<Hole>& holes, const char* what,
                              double min_circularity = 0.87) {
  double least_diameter = 1e300, least_circularity = 1e300;
  for (const Hole& h : holes) {
    EXPECT_GE(h.diameter, 0.7 * kHole)
        << what << ": hole at " << h.centre[0] << ", " << h.centre[1] << ", " << h.centre[2];
    EXPECT_GE(h.circularity, min_circularity)
        << what << ": hole at " << h.centre[0] << ", " << h.centre[1] << ", " << h.centre[2];
    EXPECT_GE(h.axis_ratio, 0.6) << what << ": hole at " << h.centre[0] << ", " << h.centre[1] << ", "
                                 << h.centre[2];
    least_diameter = std::min(least_diameter, h.diameter);
    least_circularity = std::min(least_circularity, h.circularity);
  }
  std::printf("%s: least diameter %.2f mm, least circularity %.3f\n", what, least_diameter,
              least_circularity);
}

// A sphere about the origin with a capped cylinder (the stalk) standing on its north pole along +z:
// one closed surface, welded along the circle where they meet (a concave 84 degree crease).
struct Stalk {
  double sphere = 30.0, radius = 3.0, length = 30.0;
  double base() const { return std::sqrt(sphere * sphere - radius * radius); }  // z of the junction
  double tip() const { return base() + length; }
};

Mesh sphere_with_stalk(const Stalk& g) {
  std::vector<std::array<double, 2>> profile;
  const int rings = 48, along = 30;
  const double top = std::asin(g.radius / g.sphere);  // the junction's polar angle
  for (int i = 0; i <= rings; ++i) {
    const double theta = std::numbers::pi - (std::numbers::pi - top) * i / rings;
    profile.push_back({i == 0 ? 0.0 : g.sphere * std::sin(theta), g.sphere * std::cos(theta)});
  }
  profile.back() = {g.radius, g.base()};
  for (int i = 1; i <= along; ++i) profile.push_back({g.radius, g.base() + g.length * i / along});
  profile.push_back({0.5 * g.radius, g.tip()});
  profile.push_back({0.0, g.tip()});
  return test_support::revolve(profile, 96);
}

// A cube [-a, a]^3 with edges and corners rounded with radius r: a point p of the cube maps to
// c + r (p - c) / |p - c|, c its nearest point of [-(a - r), a - r]^3. Each face's side of an edge's
// round has `facets` facets up to its 45 degree line (2 x facets per quarter circle); the flat faces are
// in cells of about `cell` mm. Vertices shared between faces are welded.
Mesh rounded_cube(double a, double r, int facets, double cell) {
  const double b = a - r;
  // Coordinates along a face from -a to a; in (b, a] the coordinate b + r tan(angle) puts the arc's
  // vertices at equal angles (a itself exactly, so that the faces' shared vertices weld).
  const auto arc = [&](int i) {
    return i == facets ? a : b + r * std::tan(std::numbers::pi / 4 * i / facets);
  };
  std::vector<double> coords;
  for (int i = facets; i > 0; --i) coords.push_back(-arc(i));
  const int flat = std::max(1, static_cast<int>(std::lround(2 * b / cell)));
  for (int i = 0; i <= flat; ++i) coords.push_back(-b + 2 * b * i / flat);
  for (int i = 1; i <= facets; ++i) coords.push_back(arc(i));
  Mesh m;
  std::map<Point, std::int32_t> index;
  const auto vertex = [&](const Point& p) {
    Point c, q;
    double length = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      c[k] = std::clamp(p[k], -b, b);
      length += (p[k] - c[k]) * (p[k] - c[k]);
    }
    length = std::sqrt(length);
    for (std::size_t k = 0; k < 3; ++k) q[k] = c[k] + r * (p[k] - c[k]) / length;
    const auto [it, added] = index.try_emplace(q, static_cast<std::int32_t>(m.vertices.size()));
    if (added) m.vertices.push_back(q);
    return it->second;
  };
  const std::size_t n = coords.size();
  for (std::size_t axis = 0; axis < 3; ++axis)
    for (double side : {-a, a}) {
      const std::size_t u = (axis + 1) % 3, v = (axis + 2) % 3;
      std::vector<std::int32_t> id(n * n);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
          Point p;
          p[axis] = side;
          p[u] = coords[i];
          p[v] = coords[j];
          id[i * n + j] = vertex(p);
        }
      for (std::size_t i = 0; i + 1 < n; ++i)
        for (std::size_t j = 0; j + 1 < n; ++j) {
          const std::int32_t p00 = id[i * n + j], p10 = id[(i + 1) * n + j], p11 = id[(i + 1) * n + j + 1],
                             p01 = id[i * n + j + 1];
          for (Triangle t : {Triangle{p00, p10, p11}, Triangle{p00, p11, p01}}) {
            // Convex about the origin: outward when the normal points away from it.
            const Point &A = m.vertices[static_cast<std::size_t>(t[0])],
                        &B = m.vertices[static_cast<std::size_t>(t[1])],
                        &C = m.vertices[static_cast<std::size_t>(t[2])];
            const Point e{B[0] - A[0], B[1] - A[1], B[2] - A[2]}, f{C[0] - A[0], C[1] - A[1], C[2] - A[2]};
            const Point normal{e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2],
                               e[0] * f[1] - e[1] * f[0]};
            if (normal[0] * A[0] + normal[1] * A[1] + normal[2] * A[2] < 0) std::swap(t[1], t[2]);
            m.triangles.push_back(t);
          }
        }
    }
  return m;
}

}  // namespace

// Issue 19: no hole on a thin cylinder attached to a sphere, one part, the holes round and whole, and
// the sphere's count within 10% of the estimate for its free area.
TEST(PrintQuality, ThinStalkOnASphereStaysWholeAndTheSphereKeepsItsHoles) {
  const Stalk g;
  MeshInput input;
  input.mesh = sphere_with_stalk(g);
  input.name = "sphere with stalk";
  const Options options = holes_options();
  const Result r = perforate(input, options);
  ASSERT_EQ(r.report.input.boundary_edges, 0) << "the test's mesh is closed";
  EXPECT_GT(r.report.input.thin_vertices, 0);
  std::printf("thin vertices %lld, crease edges %lld\n", static_cast<long long>(r.report.input.thin_vertices),
              static_cast<long long>(r.report.input.crease_edges));
  expect_one_part(r, "sphere with stalk");
  const Output& out = r.outputs[0];
  // The stalk is all there: the output reaches its cap (the wall's outer face half a wall above it).
  double top = -1e300;
  for (const Point& p : out.mesh.vertices) top = std::max(top, p[2]);
  EXPECT_NEAR(top, g.tip() + kWall / 2, 0.1) << "the stalk's tip is cut off";

  // No hole centre on the stalk, and no hole reaching it: each centre at least its own radius from the
  // circle where the stalk meets the sphere.
  double nearest = 1e300;
  std::size_t on_sphere = 0;
  for (const Hole& h : out.holes) {
    const double rho = std::hypot(h.centre[0], h.centre[1]);
    EXPECT_FALSE(h.centre[2] > g.base() - 0.5 && rho < g.radius + kWall)
        << "a hole on the stalk at height " << h.centre[2] - g.base() << " mm";
    const double to_junction = std::hypot(rho - g.radius, h.centre[2] - g.base());
    EXPECT_GE(to_junction, 0.5 * h.diameter) << "a hole reaching the stalk, centre at rho " << rho;
    nearest = std::min(nearest, to_junction);
    if (h.centre[2] < g.base()) ++on_sphere;
  }
  std::printf("nearest hole centre to the stalk's foot: %.2f mm\n", nearest);
  expect_round_whole_holes(out.holes, "sphere with stalk");

  // The sphere keeps the bare sphere's density outside the zone around the stalk's foot (holes kept half
  // a hole clear of the junction: the cap out to rho = stalk radius + half a hole, 1% of the sphere, so
  // its exact width does not matter against the bound).
  const double cap_rho = g.radius + 0.5 * kHole;
  const double cap =
      2 * std::numbers::pi * g.sphere * (g.sphere - std::sqrt(g.sphere * g.sphere - cap_rho * cap_rho));
  const double estimate =
      density_factor(options) * lattice_estimate(4 * std::numbers::pi * g.sphere * g.sphere - cap, kSpacing);
  std::printf("sphere part: %zu holes, estimate %.1f\n", on_sphere, estimate);
  EXPECT_NEAR(static_cast<double>(on_sphere), estimate, 0.10 * estimate);
  // The holes' Voronoi cells cover the free surface: the stalk's zone is nobody's cell (were it the
  // nearest holes', their cells would be several times the others').
  const double cell_cv = r.report.outputs.at(0).holes.cell_area_cv;
  std::printf("cell-area CV %.4f\n", cell_cv);
  EXPECT_LT(cell_cv, 0.10);
}

// Issue 19: no hole straddling the edges of a cube with rounded corners, and the count on the faces
// within 10% of the estimate for their free area. Run twice: with the defaults, and with the crease zone
// alone (thin_feature_ratio = 0), since the thin test also claims a strip along every convex edge (the
// inward ball near a 90 degree edge meets the next face: within 0.9 x 4.5 mm of it, plus the half-hole
// margin), which would hide a crease zone that stopped working.
TEST(PrintQuality, NoHoleStraddlesAnEdgeOfARoundedCube) {
  constexpr double kHalf = 30.0;
  MeshInput input;
  input.mesh = rounded_cube(kHalf, 2.0, 1, 2.0);
  input.name = "rounded cube";
  const double factor = density_factor(holes_options());
  for (const bool thin : {true, false}) {
    Options options = holes_options();
    if (!thin) options.thin_feature_ratio = 0.0;
    const char* what = thin ? "rounded cube" : "rounded cube, creases alone";
    const Result r = perforate(input, options);
    ASSERT_EQ(r.report.input.boundary_edges, 0) << "the test's mesh is closed";
    EXPECT_GT(r.report.input.crease_edges, 0) << "the 45 degree edges are creases";
    std::printf("%s: thin vertices %lld, crease edges %lld\n", what,
                static_cast<long long>(r.report.input.thin_vertices),
                static_cast<long long>(r.report.input.crease_edges));
    expect_one_part(r, what);
    const Output& out = r.outputs[0];
    expect_round_whole_holes(out.holes, what);

    // Each hole's centre against the edge lines of its face: axis k = the face's normal, side s; the face's
    // four edges lie at x_j = +-a for the other two axes j.
    std::array<double, 24> row{};  // per face and edge: the nearest hole centre's distance
    row.fill(1e300);
    double nearest = 1e300;
    std::int64_t straddling = 0;
    for (const Hole& h : out.holes) {
      std::size_t k = 0;
      for (std::size_t i = 1; i < 3; ++i)
        if (std::abs(h.centre[i]) > std::abs(h.centre[k])) k = i;
      const double s = h.centre[k] > 0 ? kHalf : -kHalf;
      const std::size_t face = 2 * k + (s > 0 ? 1 : 0);
      double least = 1e300;
      for (std::size_t e = 0; e < 4; ++e) {
        const std::size_t j = (k + 1 + e / 2) % 3;
        const double d = std::hypot(h.centre[k] - s, h.centre[j] - (e % 2 ? kHalf : -kHalf));
        row[4 * face + e] = std::min(row[4 * face + e], d);
        least = std::min(least, d);
      }
      nearest = std::min(nearest, least);
      if (least < 0.5 * kHole) {
        ++straddling;
        ADD_FAILURE() << what << ": a hole straddles an edge, centre " << h.centre[0] << ", " << h.centre[1]
                      << ", " << h.centre[2] << ", " << least << " mm from the edge line";
      }
    }
    // The free face: a hexagonal pattern's outer row of holes covers half a row pitch (sqrt(3)/4 s)
    // beyond its centres, so each face is free to the mean outer row's distance from its edges less that.
    double mean_row = 0.0;
    for (double d : row) {
      ASSERT_LT(d, kHalf) << what << ": a face without holes";
      mean_row += d / 24;
    }
    const double free_side = 2 * kHalf - 2 * std::max(0.0, mean_row - std::sqrt(3.0) / 4 * kSpacing);
    const double estimate = factor * lattice_estimate(6 * free_side * free_side, kSpacing);
    std::printf(
        "%s: nearest hole centre to an edge line %.2f mm, mean outer row %.2f mm, free face %.1f mm "
        "square; %zu holes, estimate %.1f; %lld within half a hole of an edge\n",
        what, nearest, mean_row, free_side, out.holes.size(), estimate, static_cast<long long>(straddling));
    EXPECT_NEAR(static_cast<double>(out.holes.size()), estimate, 0.10 * estimate) << what;
  }
}

// Issue 19: single component and no void on an open sleeve.
TEST(PrintQuality, OpenSleeveIsOnePart) {
  MeshInput input;
  input.mesh = test_support::open_sleeve(35.0, 100.0, 128, 50);
  input.name = "sleeve";
  Options options;
  options.hole_diameter = 8.0;
  options.spacing = 12.0;
  options.wall = kWall;
  options.rim = 3.0;
  const Result r = perforate(input, options);
  expect_one_part(r, "sleeve");
  EXPECT_GT(r.outputs[0].holes.size(), 100u);  // 2 pi 35 x 94 mm of free surface: about 130
}

// Issue 19 on the bundled scan, as a user runs it (6 mm holes at 10 mm, 2 mm wall, defaults): one part,
// and every hole whole: none narrower than 0.7 of the request on the written mesh, none pinched, none
// with an axis ratio under 0.6. Seeds 1-3 measured 4.30-5.04 mm, circularity 0.865-0.951 and axis
// ratio 0.634-0.732 at the least. It fails if the run stops by the paper's rule from the even layout
// (seed 1: two discs still merging at step 30, a figure-eight hole of circularity 0.48), or if spots
// are closed by their band area at 0.7 D (loops down to 4.18 mm).
TEST(PrintQuality, BunnyScanHolesAreWhole) {
  const MeshInput bunny =
      load_mesh(std::filesystem::path(PORESHELL_DATA_DIR) / "stanford-bunny.obj", Unit::m);
  const Result r = perforate(bunny, holes_options());
  expect_one_part(r, "bunny");
  const std::vector<Hole>& holes = r.outputs[0].holes;
  ASSERT_GT(holes.size(), 350u);  // 415 measured
  expect_round_whole_holes(holes, "bunny", 0.8);
}
