// Issue 51, on generated shapes, through the public API: what a scan brings that a clean model does not,
// each asserted on the written mesh.
//
// - The wall: with holes asked in mm and no `wall`, 2 mm whatever the hole size (before: 3.81 voxels of
//   the hole map's grid, 3.75, 3.14 and 4.70 mm on the sleeve for three hole sizes).
// - A sealed cavity: a sphere (r 30 mm) with a tail (a capsule of r 4 mm, 20 mm long) on a neck narrower
//   than the wall. The tail is thin (no hole), the neck solid, so the tail's inside (some 500 mm^3, over
//   the 1% removal threshold) is sealed off from the sphere's, which the pores open: before, a second
//   part; now filled, one part, and the report says so.
// - Thin at the hole's scale: a sphere (r 40 mm) whose surface is grooved and bumped like a scan's relief
//   (grooves 3 mm deep every 6.3 mm along the meridians, bumps across them) is thick everywhere: the
//   thin-feature rule keeps its holes (before: every vertex marked thin, no hole at all).
// - The bunny scan at 6 / 10 mm with the defaults (its base's open edges get a 3 mm rim): before the
//   rim rule a hole left 2.94 mm of the 3 mm rim, and one at the base-to-body turn measured axis ratio
//   0.52; the first is closed now, the second cut to a round hole (the rim 3.63 mm, the least axis
//   ratio 0.81).
// - An open outline: a flat sheet whose outline is jagged (r = 45 + 4 sin 7 theta mm), and a square
//   sheet (100 mm) with a slit 1 mm wide and 40 mm long cut in from one side. With the defaults (a rim of
//   half a hole) no hole is cut by the outline or joins the slit: every band spot is a pore of the mesh
//   and the nearest hole's edge is clear of the boundary. `rim` 0 still allows notches (on the slit).
// - A narrow face between two bends: a box 80 x 17 x 40 mm with sharp edges, whose 17 mm faces keep a
//   strip of about 8 mm between the crease zones, where the equation leaves slots (fandisk's case). The
//   oblong spots are cut to round holes: least mid-wall axis ratio 0.63 before (the band's 0.65 closed
//   none of them), 0.76 now, with the same 56 holes.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

// The sphere, a neck of radius `neck` from its north pole up `neck_length`, then the tail: a cylinder of
// radius `tail` and length `tail_length`, capped by a half sphere.
Mesh sphere_with_sealed_tail(double sphere, double neck, double neck_length, double tail,
                             double tail_length) {
  std::vector<std::array<double, 2>> profile;
  const int rings = 60;
  const double top = std::asin(neck / sphere);
  for (int i = 0; i <= rings; ++i) {
    const double theta = std::numbers::pi - (std::numbers::pi - top) * i / rings;
    profile.push_back({i == 0 ? 0.0 : sphere * std::sin(theta), sphere * std::cos(theta)});
  }
  const double base = sphere * std::cos(top);
  for (int i = 1; i <= 4; ++i) profile.push_back({neck, base + neck_length * i / 4});
  const double start = base + neck_length;
  for (int i = 0; i <= 20; ++i) profile.push_back({tail, start + tail_length * i / 20});
  for (int i = 1; i <= 8; ++i) {
    const double a = std::numbers::pi / 2 * i / 8;
    profile.push_back({i == 8 ? 0.0 : tail * std::cos(a), start + tail_length + tail * std::sin(a)});
  }
  return test_support::revolve(profile, 96);
}

// A flat sheet in z = 0 (normals +z) inside the outline r(theta) = radius + bump sin(lobes theta).
Mesh jagged_sheet(double radius, double bump, int lobes, int rings = 40, int segments = 256) {
  Mesh m;
  m.vertices.push_back({0, 0, 0});
  for (int k = 1; k <= rings; ++k)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * std::numbers::pi * s / segments;
      const double r = (radius + bump * std::sin(lobes * a)) * k / rings;
      m.vertices.push_back({r * std::cos(a), r * std::sin(a), 0.0});
    }
  const auto at = [&](int k, int s) {
    return static_cast<std::int32_t>(1 + (k - 1) * segments + s % segments);
  };
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({0, at(1, s), at(1, s + 1)});
    for (int k = 1; k < rings; ++k) {
      m.triangles.push_back({at(k, s), at(k + 1, s), at(k + 1, s + 1)});
      m.triangles.push_back({at(k, s), at(k + 1, s + 1), at(k, s + 1)});
    }
  }
  return m;
}

// A square sheet [0, n]^2 mm in z = 0 of 1 mm cells (normals +z), less the cells of column `slit` from
// y = 0 up to `slit_length`: a slit 1 mm wide cut in from the side y = 0.
Mesh slit_sheet(int n, int slit, int slit_length) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.push_back({double(i), double(j), 0.0});
  const auto at = [&](int i, int j) { return static_cast<std::int32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i == slit && j < slit_length) continue;
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

// A sphere of radius r whose surface carries a scan's relief: grooves of depth 2a around the z axis,
// `grooves` of them from pole to pole, and bumps of a/2 across them.
Mesh grooved_sphere(double r, double a, int grooves, int rings = 300, int segments = 300) {
  Mesh m;
  m.vertices.push_back({0, 0, -r});
  for (int i = 1; i < rings; ++i) {
    const double theta = std::numbers::pi * i / rings;  // from the south pole
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      const double rho = r + a * std::sin(2 * grooves * theta) * std::sqrt(std::sin(theta)) +
                         0.5 * a * std::sin(17 * phi + 3 * theta) * std::sin(theta);
      m.vertices.push_back({rho * std::sin(theta) * std::cos(phi), rho * std::sin(theta) * std::sin(phi),
                            -rho * std::cos(theta)});
    }
  }
  const auto top = static_cast<std::int32_t>(m.vertices.size());
  m.vertices.push_back({0, 0, r});
  const auto at = [&](int i, int s) {
    return static_cast<std::int32_t>(1 + (i - 1) * segments + s % segments);
  };
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({0, at(1, s + 1), at(1, s)});
    for (int i = 1; i + 1 < rings; ++i) {
      m.triangles.push_back({at(i, s), at(i, s + 1), at(i + 1, s + 1)});
      m.triangles.push_back({at(i, s), at(i + 1, s + 1), at(i + 1, s)});
    }
    m.triangles.push_back({at(rings - 1, s), at(rings - 1, s + 1), top});
  }
  return m;
}

// A closed box [-x/2, x/2] x [-y/2, y/2] x [-z/2, z/2] with sharp edges, each face a grid of cells about
// `cell` mm (two triangles each), normals outward.
Mesh sharp_box(const std::array<double, 3>& size, double cell) {
  Mesh m;
  std::array<int, 3> n{};
  for (int a = 0; a < 3; ++a) n[a] = std::max(2, static_cast<int>(std::lround(size[a] / cell)));
  std::map<std::array<int, 3>, std::int32_t> index;  // grid coordinates: faces share their edges
  const auto vertex = [&](const std::array<int, 3>& key) {
    const auto [it, added] = index.try_emplace(key, static_cast<std::int32_t>(m.vertices.size()));
    if (added) {
      std::array<double, 3> p{};
      for (int a = 0; a < 3; ++a) p[a] = size[a] * (static_cast<double>(key[a]) / n[a] - 0.5);
      m.vertices.push_back(p);
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (const int side : {0, 1}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < n[u]; ++i)
        for (int j = 0; j < n[v]; ++j) {
          std::array<std::int32_t, 4> quad{};
          const std::array<std::array<int, 2>, 4> corners{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
          for (std::size_t c = 0; c < 4; ++c) {
            std::array<int, 3> key{};
            key[axis] = side * n[axis];
            key[u] = i + corners[c][0];
            key[v] = j + corners[c][1];
            quad[c] = vertex(key);
          }
          if (side == 1) {
            m.triangles.push_back({quad[0], quad[1], quad[2]});
            m.triangles.push_back({quad[0], quad[2], quad[3]});
          } else {
            m.triangles.push_back({quad[0], quad[2], quad[1]});
            m.triangles.push_back({quad[0], quad[3], quad[2]});
          }
        }
    }
  return m;
}

}  // namespace

TEST(ScanCases, TheDefaultWallIsTwoMillimetresWhateverTheHoleSize) {
  for (const double d : {6.0, 8.0, 10.0}) {
    MeshInput input;
    input.mesh = test_support::open_sleeve(35.0, 100.0, 128, 50);
    Options o;
    o.hole_diameter = d;
    o.spacing = 1.6 * d;
    o.rim = 3.0;
    const Result r = perforate(input, o);
    const LevelReport& level = r.report.outputs.at(0);
    std::printf("holes %.0f mm: wall asked %.3g mm (%s), measured median %.3g mm\n", d,
                r.report.solid.wall_mm, r.report.solid.wall_source.c_str(), level.wall.median);
    EXPECT_DOUBLE_EQ(r.report.solid.wall_mm, kDefaultWallMm);
    EXPECT_EQ(r.report.solid.wall_source, "default");
    EXPECT_NEAR(level.wall.median, kDefaultWallMm, 0.1 * kDefaultWallMm);
  }
}

TEST(ScanCases, ASealedCavityIsFilledAndTheOutputIsOnePart) {
  MeshInput input;
  input.mesh = sphere_with_sealed_tail(30.0, 0.6, 4.0, 4.0, 20.0);
  input.name = "sphere with a sealed tail";
  Options o;
  o.hole_diameter = 6.0;
  o.spacing = 10.0;
  const Result r = perforate(input, o);
  const LevelReport& level = r.report.outputs.at(0);
  std::printf("%lld part(s), %lld component(s); filled %lld cavities, %.1f mm^3; %zu holes\n",
              static_cast<long long>(level.parts.parts), static_cast<long long>(level.topology.components),
              static_cast<long long>(level.parts.filled_cavities), level.parts.filled_volume,
              r.outputs.at(0).holes.size());
  EXPECT_EQ(level.topology.components, 1);
  EXPECT_EQ(level.parts.parts, 1);
  EXPECT_TRUE(level.topology.closed && level.topology.manifold && level.topology.oriented);
  EXPECT_GE(level.parts.filled_cavities, 1);
  // The tail's inside within the 2 mm wall: radius 3 mm over 20 mm and a half ball, less the meshing.
  EXPECT_GT(level.parts.filled_volume, 300.0);
  EXPECT_GT(r.outputs.at(0).holes.size(), 50u);
  // keep_fragments keeps it, as before: the cavity is there to fill.
  o.keep_fragments = true;
  EXPECT_GE(perforate(input, o).report.outputs.at(0).topology.components, 2);
}

TEST(ScanCases, NoHoleIsCutByAnOpenOutlineByDefault) {
  MeshInput input;
  input.mesh = jagged_sheet(45.0, 4.0, 7);
  input.name = "jagged sheet";
  Options o;
  o.hole_diameter = 6.0;
  o.spacing = 10.0;
  const Result r = perforate(input, o);
  const LevelReport& level = r.report.outputs.at(0);
  std::printf("default: rim asked %.3g mm, left %.3g mm; %zu holes, %lld spots no pore (notches)\n",
              level.zones.rim_asked, level.zones.rim, r.outputs.at(0).holes.size(),
              static_cast<long long>(level.hole_table_dropped));
  EXPECT_DOUBLE_EQ(level.zones.rim_asked, 3.0);
  EXPECT_EQ(level.hole_table_dropped, 0);
  EXPECT_GE(level.zones.rim, 0.0);  // no hole reaches the outline
  EXPECT_GT(r.outputs.at(0).holes.size(), 30u);
  EXPECT_EQ(level.topology.components, 1);
  o.rim = 0.0;
  const Result open = perforate(input, o);
  const LevelReport& notched = open.report.outputs.at(0);
  std::printf("rim 0: rim left %.3g mm; %zu holes, %lld spots no pore (notches)\n", notched.zones.rim,
              open.outputs.at(0).holes.size(), static_cast<long long>(notched.hole_table_dropped));
  EXPECT_DOUBLE_EQ(notched.zones.rim_asked, 0.0);
}

TEST(ScanCases, NoHoleJoinsASlitByDefault) {
  MeshInput input;
  input.mesh = slit_sheet(100, 50, 40);
  input.name = "sheet with a slit";
  Options o;
  o.hole_diameter = 6.0;
  o.spacing = 10.0;
  const Result r = perforate(input, o);
  const LevelReport& level = r.report.outputs.at(0);
  std::printf("default: rim asked %.3g mm, left %.3g mm; %zu holes, %lld spots no pore (notches)\n",
              level.zones.rim_asked, level.zones.rim, r.outputs.at(0).holes.size(),
              static_cast<long long>(level.hole_table_dropped));
  EXPECT_EQ(level.hole_table_dropped, 0);
  EXPECT_GE(level.zones.rim, 0.0);
  EXPECT_GT(r.outputs.at(0).holes.size(), 40u);
  EXPECT_EQ(level.topology.components, 1);
  o.rim = 0.0;
  const Result open = perforate(input, o);
  const LevelReport& notched = open.report.outputs.at(0);
  std::printf("rim 0: rim left %.3g mm; %zu holes, %lld spots no pore (notches)\n", notched.zones.rim,
              open.outputs.at(0).holes.size(), static_cast<long long>(notched.hole_table_dropped));
  EXPECT_TRUE(notched.hole_table_dropped > 0 || notched.zones.rim < 0.0);
}

TEST(ScanCases, AGroovedThickBodyKeepsItsHoles) {
  MeshInput input;
  input.mesh = grooved_sphere(40.0, 1.5, 20);
  input.name = "grooved sphere";
  Options o;
  o.hole_diameter = 6.0;
  o.spacing = 10.0;
  const Result r = perforate(input, o);
  o.thin_feature_ratio = 0.0;
  const Result off = perforate(input, o);
  const std::size_t with = r.outputs.at(0).holes.size(), without = off.outputs.at(0).holes.size();
  std::printf("thin rule on: %lld of %lld vertices thin, %zu holes, porosity %.3f; off: %zu holes, %.3f\n",
              static_cast<long long>(r.report.input.thin_vertices),
              static_cast<long long>(r.report.input.vertices), with, r.report.outputs.at(0).holes.porosity,
              without, off.report.outputs.at(0).holes.porosity);
  EXPECT_LT(r.report.input.thin_vertices, r.report.input.vertices / 20);
  EXPECT_GE(static_cast<double>(with), 0.9 * static_cast<double>(without));
  EXPECT_GT(without, 150u);
}

TEST(ScanCases, TheBunnysRimIsTheRimAskedAndNoHoleIsOblong) {
  const MeshInput bunny = load_mesh(std::string(PORESHELL_DATA_DIR) + "/stanford-bunny.obj", Unit::m);
  Options o;
  o.hole_diameter = 6.0;
  o.spacing = 10.0;
  const Result r = perforate(bunny, o);
  const LevelReport& level = r.report.outputs.at(0);
  double least_axis = 1.0;
  for (const Hole& h : r.outputs.at(0).holes) least_axis = std::min(least_axis, h.axis_ratio);
  std::printf(
      "bunny: rim asked %.3g mm, left %.3g mm; %zu holes, least axis ratio %.2f; closed %lld oblong, "
      "%lld in the rim\n",
      level.zones.rim_asked, level.zones.rim, r.outputs.at(0).holes.size(), least_axis,
      static_cast<long long>(r.report.pattern.closed_oblong_holes),
      static_cast<long long>(r.report.pattern.closed_rim_holes));
  EXPECT_DOUBLE_EQ(level.zones.rim_asked, 3.0);
  EXPECT_GE(level.zones.rim, level.zones.rim_asked);
  EXPECT_GE(least_axis, 0.6);
  EXPECT_EQ(level.topology.components, 1);
}

TEST(ScanCases, NoHoleIsOblongOnANarrowFaceBetweenTwoBends) {
  MeshInput input;
  input.mesh = sharp_box({80.0, 17.0, 40.0}, 1.0);
  input.name = "box with narrow faces";
  Options o;
  o.hole_diameter = 6.0;
  o.spacing = 10.0;
  const Result r = perforate(input, o);
  const std::vector<Hole>& holes = r.outputs.at(0).holes;
  double least_axis = 1.0;
  for (const Hole& h : holes) least_axis = std::min(least_axis, h.axis_ratio);
  std::printf(
      "box: %zu holes, least axis ratio %.3f; %lld oblong spots rounded, %lld closed; porosity %.3f\n",
      holes.size(), least_axis, static_cast<long long>(r.report.pattern.rounded_oblong_holes),
      static_cast<long long>(r.report.pattern.closed_oblong_holes), r.report.outputs.at(0).holes.porosity);
  EXPECT_GE(least_axis, 0.7);
  EXPECT_GT(r.report.pattern.rounded_oblong_holes, 0);
  // Rounded, not closed: the holes the narrow faces carry stay.
  EXPECT_GE(holes.size(), 50u);
  EXPECT_EQ(r.report.outputs.at(0).topology.components, 1);
}
