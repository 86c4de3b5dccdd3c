// The hole table on meshes made here: a plate with one hole through it (a thick washer) whose hole is a
// polygon of known area and perimeter, in a tilted frame. The table reads the polygon's diameter and
// circularity (circle, ellipse, square), finds the hole from a seed off its centre or off the wall's
// middle, re-seats a tilted cut, traces a hole the sampled cut misses, drops seeds in the solid, and
// gives each hole its nearest neighbour. Then round pores made by the shell's own mesher on a sphere,
// also in a wall that curves away from the tangent plane within a hole's radius.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "band/band.hpp"
#include "measure/hole_table.hpp"

namespace poreshell {
namespace {

using Polygon = std::vector<Eigen::Vector2d>;  // counter-clockwise, star-shaped about the origin

Polygon circle(double r, int sides) {
  Polygon p;
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * std::numbers::pi * i / sides;
    p.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return p;
}

Polygon ellipse(double a, double b, int sides) {
  Polygon p = circle(1.0, sides);
  for (auto& q : p) q = Eigen::Vector2d(a * q.x(), b * q.y());
  return p;
}

Polygon square(double half, int per_side) {
  Polygon p;
  const Eigen::Vector2d corners[] = {{half, -half}, {half, half}, {-half, half}, {-half, -half}};
  for (int c = 0; c < 4; ++c)
    for (int i = 0; i < per_side; ++i)
      p.push_back(corners[c] + (corners[(c + 1) % 4] - corners[c]) * (static_cast<double>(i) / per_side));
  return p;
}

double area_of(const Polygon& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& u = p[i];
    const auto& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return a / 2;
}

double perimeter_of(const Polygon& p) {
  double s = 0;
  for (std::size_t i = 0; i < p.size(); ++i) s += (p[(i + 1) % p.size()] - p[i]).norm();
  return s;
}

// A plate of thickness t, z in [-t/2, t/2], with the hole through it and an outer edge 3 times the hole
// (scaled about the origin); the hole's wall has a ring of vertices at z = 0, so the middle plane passes
// through vertices. Closed and outward oriented; placed by x -> rotation x + shift.
void add_washer(TriangleMesh& m, const Polygon& hole, double t, const Eigen::Matrix3d& rotation,
                const Vec3& shift) {
  const auto n = static_cast<std::int32_t>(hole.size());
  const auto base = static_cast<std::int32_t>(m.vertices.size());
  const auto ring = [&](double scale, double z) {
    for (const auto& q : hole) m.vertices.push_back(rotation * Vec3(scale * q.x(), scale * q.y(), z) + shift);
  };
  ring(1, -t / 2);  // ring 0: hole, bottom
  ring(1, 0);       // ring 1: hole, middle
  ring(1, t / 2);   // ring 2: hole, top
  ring(3, -t / 2);  // ring 3: edge, bottom
  ring(3, t / 2);   // ring 4: edge, top
  const auto at = [&](int r, std::int32_t i) { return base + r * n + (i % n); };
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t j = i + 1;
    m.triangles.push_back({at(2, i), at(4, i), at(4, j)});  // top
    m.triangles.push_back({at(2, i), at(4, j), at(2, j)});
    m.triangles.push_back({at(0, i), at(3, j), at(3, i)});  // bottom
    m.triangles.push_back({at(0, i), at(0, j), at(3, j)});
    m.triangles.push_back({at(3, i), at(3, j), at(4, j)});  // outer edge
    m.triangles.push_back({at(3, i), at(4, j), at(4, i)});
    for (int r = 0; r < 2; ++r) {  // the hole's wall, facing its axis
      m.triangles.push_back({at(r, i), at(r + 1, j), at(r, j)});
      m.triangles.push_back({at(r, i), at(r + 1, i), at(r + 1, j)});
    }
  }
}

const Eigen::Matrix3d kTilt =
    (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(0.3, Vec3::UnitX())).matrix();
const Vec3 kShift(12.0, -7.0, 30.0);
constexpr double kWall = 2.0;

TriangleMesh washer(const Polygon& hole) {
  TriangleMesh m;
  add_washer(m, hole, kWall, kTilt, kShift);
  return m;
}

// A seed at plate coordinates (x, y, z), normal along the plate's +z (or -z).
HoleSeed seed_at(double x, double y, double z, double reach, double normal_sign = 1.0) {
  return {kTilt * Vec3(x, y, z) + kShift, normal_sign * (kTilt * Vec3::UnitZ()), reach};
}

TEST(HoleTable, TheWasherIsAClosedOutwardTorus) {
  const MeshTopology t = analyze_topology(washer(circle(3.0, 64)));
  EXPECT_TRUE(t.closed() && t.manifold() && t.oriented());
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_GT(t.signed_volume, 0.0);
}

TEST(HoleTable, CircularHoleGivesThePolygonsDiameterAndCircularityNearOne) {
  const Polygon hole = circle(3.0, 256);
  const double area = area_of(hole), perimeter = perimeter_of(hole);
  const TriangleMesh mesh = washer(hole);
  // At the middle (through vertices), off it, from either side, and from a seed 0.4 r off the axis.
  for (const HoleSeed& seed : {seed_at(0, 0, 0, 5), seed_at(0, 0, 0.37, 5), seed_at(0, 0, 0, 5, -1.0),
                               seed_at(1.2, -0.3, -0.5, 5)}) {
    const HoleTable table = measure_holes(mesh, std::span(&seed, 1));
    ASSERT_EQ(table.holes.size(), 1u);
    EXPECT_EQ(table.dropped, 0u);
    const HoleRecord& r = table.holes[0];
    EXPECT_NEAR(r.diameter, std::sqrt(4 * area / std::numbers::pi), 1e-9);
    EXPECT_NEAR(r.diameter, 6.0, 0.01);
    EXPECT_NEAR(r.circularity, 4 * std::numbers::pi * area / (perimeter * perimeter), 1e-9);
    EXPECT_GT(r.circularity, 0.999);
    // The centre is on the hole's axis, in the seed's plane; the normal is the seed's.
    const Vec3 local = kTilt.transpose() * (r.centre - kShift);
    EXPECT_NEAR(local.x(), 0.0, 1e-9);
    EXPECT_NEAR(local.y(), 0.0, 1e-9);
    EXPECT_NEAR(local.z(), kTilt.transpose().row(2).dot(seed.point - kShift), 1e-9);
    EXPECT_NEAR((r.normal - seed.normal).norm(), 0.0, 1e-12);
    EXPECT_EQ(r.nearest, 0.0);  // alone
  }
}

TEST(HoleTable, EllipticalAndSquareHolesGiveTheirShapesCircularityAndAxisRatio) {
  // Ellipse 4 x 2: A = pi a b, P by Ramanujan's second formula (error far below the polygon's).
  const double a = 4, b = 2, h = (a - b) * (a - b) / ((a + b) * (a + b));
  const double ellipse_perimeter = std::numbers::pi * (a + b) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
  const double ellipse_circularity =
      4 * std::numbers::pi * (std::numbers::pi * a * b) / (ellipse_perimeter * ellipse_perimeter);  // 0.8000
  const HoleSeed seed = seed_at(0.5, 0.3, 0.2, 8);
  const HoleTable e = measure_holes(washer(ellipse(a, b, 512)), std::span(&seed, 1));
  ASSERT_EQ(e.holes.size(), 1u);
  EXPECT_NEAR(e.holes[0].circularity, ellipse_circularity, 1e-3);
  EXPECT_NEAR(e.holes[0].diameter, 2 * std::sqrt(a * b), 1e-3);
  EXPECT_NEAR(e.holes[0].axis_ratio, b / a, 1e-3);

  const HoleTable s = measure_holes(washer(square(2.0, 16)), std::span(&seed, 1));
  ASSERT_EQ(s.holes.size(), 1u);
  EXPECT_NEAR(s.holes[0].circularity, std::numbers::pi / 4, 1e-9);
  EXPECT_NEAR(s.holes[0].diameter, std::sqrt(4 * 16 / std::numbers::pi), 1e-9);
  EXPECT_NEAR(s.holes[0].axis_ratio, 1.0, 1e-9);  // a square's second moments are equal in every direction
}

// A seed in the solid, beside the hole or beyond the plate, or whose reach does not hold the hole's
// whole loop, measures nothing: it is dropped and counted.
TEST(HoleTable, SeedsWithNoOpeningAroundThemAreDropped) {
  const TriangleMesh mesh = washer(circle(3.0, 128));
  const std::vector<HoleSeed> seeds{
      seed_at(6, 0, 0, 20),   // in the plate, within reach of its whole outer edge (a loop around it)
      seed_at(6, 0, 0, 10),   // in the plate, the hole's loop in reach but not around it
      seed_at(20, 0, 0, 5),   // off the plate
      seed_at(0.5, 0, 0, 3),  // in the hole, but the reach cuts its loop open
      seed_at(0, 0, 0, 0),    // no reach
      seed_at(0, 0, 0, 4),    // measured
  };
  const HoleTable table = measure_holes(mesh, seeds);
  ASSERT_EQ(table.holes.size(), 1u);
  EXPECT_EQ(table.dropped, 5u);
  EXPECT_NEAR(table.holes[0].diameter, 6.0, 0.01);
}

// The plate's middle plane as a mid-wall: its seeds counted. Lopsided: its points lie 5 above the
// middle beyond 2.9 from the hole's axis on the +x side (the model cut leaves the wall there), and
// without `exact` it has no heights (no trace either).
struct PlateMiddle final : MidWall {
  bool lopsided = false, exact = true;
  mutable std::atomic<int> seeds = 0;
  std::optional<HoleSeed> seed(const Vec3& x) const override {
    ++seeds;
    return HoleSeed{*point(x, Vec3::Zero()), kTilt * Vec3::UnitZ(), 0.0};
  }
  std::optional<Vec3> point(const Vec3& x, const Vec3&) const override {
    Vec3 local = kTilt.transpose() * (x - kShift);
    local.z() = lopsided && local.x() > 0.0 && local.head<2>().norm() > 2.9 ? 5.0 : 0.0;
    return kTilt * local + kShift;
  }
  std::optional<double> height(const Vec3& x, const Vec3&) const override {
    if (!exact) return std::nullopt;
    return (kTilt.transpose() * (x - kShift)).z();
  }
};

// A seed off the axis on a plane tilted 10 degrees cuts an ellipse off centre; with the mid-wall the
// hole is cut again at the loop's centre, on the plate's own middle plane.
TEST(HoleTable, ASeedOffTheHoleIsReseatedAtItsMidWall) {
  const Polygon hole = circle(3.0, 256);
  const TriangleMesh mesh = washer(hole);
  const double angle = 10 * std::numbers::pi / 180;
  const Vec3 tilted = kTilt * Vec3(std::sin(angle), 0, std::cos(angle));
  const HoleSeed seed{kTilt * Vec3(1.0, 0.5, 0.0) + kShift, tilted, 6.0};
  const HoleTable plain = measure_holes(mesh, std::span(&seed, 1));
  ASSERT_EQ(plain.holes.size(), 1u);
  EXPECT_NEAR(plain.holes[0].diameter, 6.0 / std::sqrt(std::cos(angle)), 0.01);  // the oblique cut

  const PlateMiddle middle;
  const HoleTable table = measure_holes(mesh, std::span(&seed, 1), &middle);
  ASSERT_EQ(table.holes.size(), 1u);
  EXPECT_EQ(middle.seeds, 1);
  EXPECT_NEAR(table.holes[0].diameter, std::sqrt(4 * area_of(hole) / std::numbers::pi), 1e-9);
  EXPECT_GT(table.holes[0].circularity, 0.999);
  EXPECT_NEAR((kTilt.transpose() * (table.holes[0].centre - kShift)).norm(), 0.0, 1e-9);
}

// Where the cut along the sampled middle leaves the wall, the hole's loop at the middle is traced
// across the mesh with the mid-wall's heights: the polygon itself, as from the plane.
TEST(HoleTable, AHoleTheModelCutMissesIsTracedAtTheMiddle) {
  const Polygon hole = circle(3.0, 256);
  const TriangleMesh mesh = washer(hole);
  const HoleSeed seed = seed_at(0.2, -0.1, 0, 5);
  PlateMiddle middle;
  middle.lopsided = true;
  const HoleTable table = measure_holes(mesh, std::span(&seed, 1), &middle);
  ASSERT_EQ(table.holes.size(), 1u);
  EXPECT_NEAR(table.holes[0].diameter, std::sqrt(4 * area_of(hole) / std::numbers::pi), 1e-9);
  EXPECT_NEAR(table.holes[0].circularity,
              4 * std::numbers::pi * area_of(hole) / std::pow(perimeter_of(hole), 2), 1e-9);
  EXPECT_NEAR((kTilt.transpose() * (table.holes[0].centre - kShift)).norm(), 0.0, 1e-9);
  middle.exact = false;
  EXPECT_EQ(measure_holes(mesh, std::span(&seed, 1), &middle).holes.size(), 0u);
}

// Three plates 20 and 30 mm apart: each hole's nearest centre; a second seed in one hole is dropped.
// The same table whatever the thread count.
TEST(HoleTable, NearestNeighboursAndOneRecordPerHoleWhateverTheThreads) {
  TriangleMesh mesh;
  const Vec3 x = kTilt.col(0);
  for (const double at : {0.0, 20.0, 50.0}) add_washer(mesh, circle(3.0, 96), kWall, kTilt, kShift + at * x);
  const std::vector<HoleSeed> seeds{seed_at(50, 0, 0, 5), seed_at(0.5, 0, 0, 5), seed_at(20, 0.2, 0, 5),
                                    seed_at(-0.5, 0.3, 0.1, 5)};
  const HoleTable table = measure_holes(mesh, seeds);
  ASSERT_EQ(table.holes.size(), 3u);
  EXPECT_EQ(table.dropped, 1u);
  EXPECT_NEAR(table.holes[0].nearest, 30.0, 1e-9);  // seed order: the plate at 50 first
  EXPECT_NEAR(table.holes[1].nearest, 20.0, 1e-9);
  EXPECT_NEAR(table.holes[2].nearest, 20.0, 1e-9);

  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const HoleTable serial = measure_holes(mesh, seeds);
  ASSERT_EQ(serial.holes.size(), table.holes.size());
  for (std::size_t i = 0; i < serial.holes.size(); ++i) {
    EXPECT_EQ(serial.holes[i].centre, table.holes[i].centre);
    EXPECT_EQ(serial.holes[i].diameter, table.holes[i].diameter);
    EXPECT_EQ(serial.holes[i].circularity, table.holes[i].circularity);
    EXPECT_EQ(serial.holes[i].nearest, table.holes[i].nearest);
  }
}

// The mid-wall seed on a sphere of radius 10 (signed distance): on the surface, outward unit normal,
// moved by half the wall for an outside or inside wall.
TEST(HoleTable, MidWallSeedOnASphere) {
  const Sphere sphere(Vec3(1, 2, 3), 10.0);
  const Vec3 dir = Vec3(0.3, -0.5, 0.8).normalized();
  for (const auto& [offset, shift] :
       {std::pair{WallOffset::centered, 0.0}, std::pair{WallOffset::outside, 1.0},
        std::pair{WallOffset::inside, -1.0}}) {
    const auto seed = SurfaceMidWall(sphere, 0.5, 2.0, offset, {}).seed(Vec3(1, 2, 3) + 9.7 * dir);
    ASSERT_TRUE(seed);
    // The plane fitted to a cap of radius h: off by a small part of (h / R)^2 = 0.0025.
    EXPECT_NEAR((seed->normal - dir).norm(), 0.0, 1e-4);
    EXPECT_NEAR((seed->point - (Vec3(1, 2, 3) + (10.0 + shift) * dir)).norm(), 0.0, 1e-4);
    // Frames: x_mesh = 2 x_surface + (1, 0, 0).
    const auto framed = SurfaceMidWall(sphere, 0.5, 2.0, offset, {}, 2.0, Vec3(1, 0, 0))
                            .seed(2.0 * (Vec3(1, 2, 3) + 9.7 * dir) + Vec3(1, 0, 0));
    ASSERT_TRUE(framed);
    EXPECT_NEAR((framed->point - (2.0 * seed->point + Vec3(1, 0, 0))).norm(), 0.0, 1e-9);
    EXPECT_NEAR((framed->normal - seed->normal).norm(), 0.0, 1e-12);
  }
}

// Round pores cut by the shell's own mesher: 12 spots of geodesic radius `spot` at an icosahedron's
// vertices on a sphere of radius 0.3 (grid h = 1/64).
struct IcosahedronPores {
  static constexpr double kRadius = 0.3, kH = 1.0 / 64;
  Vec3 centre = Vec3::Constant(0.5);
  Sphere sphere{centre, kRadius};
  Grid grid = Grid::fitted(Box{Vec3::Zero(), Vec3::Ones()}, 65);
  NarrowBand band = build_band(sphere, grid);
  std::vector<Vec3> spots;
  std::vector<double> phi;

  explicit IcosahedronPores(double spot) {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    for (double s : {-1.0, 1.0})
      for (double r : {-1.0, 1.0})
        for (const Vec3& d : {Vec3(0, s, r * g), Vec3(s, r * g, 0), Vec3(r * g, 0, s)})
          spots.push_back(d.normalized());
    for (const Coord& c : band.voxels()) {
      const Vec3 u = (grid.position(c) - centre).normalized();
      double nearest = INFINITY;
      for (const Vec3& d : spots)
        nearest = std::min(nearest, kRadius * std::acos(std::clamp(u.dot(d), -1.0, 1.0)));
      phi.push_back(std::tanh((spot - nearest) / 0.02));
    }
  }
  TriangleMesh mesh(double thickness, WallOffset offset) const {
    ShellOptions options;
    options.thickness = thickness;
    options.offset = offset;
    options.pattern_length = kH;
    return shell_mesh(sample_shell(sphere, band, phi, options), 0.0);
  }
  std::vector<HoleSeed> seeds(const MidWall& mid_wall, double reach) const {
    std::vector<Vec3> at;
    for (const Vec3& d : spots) at.push_back(centre + kRadius * d);
    return seeds_near(mid_wall, at, std::vector<double>(at.size(), reach));
  }
};

// Each spot's rim at the wall's middle (radius R_mid) is a circle of radius R_mid sin(spot / R) about
// the spot's axis, seen along it; the centres lie on the middle sphere, an icosahedron's edge apart.
TEST(HoleTable, RoundPoresOfTheShellMesherOnASphere) {
  const double spot = 0.06, h = IcosahedronPores::kH;
  const IcosahedronPores pores(spot);
  for (const auto& [offset, shift] :
       {std::pair{WallOffset::centered, 0.0}, std::pair{WallOffset::outside, 0.5}}) {
    const SurfaceMidWall middle(pores.sphere, h, 4 * h, offset, {});
    const HoleTable table = measure_holes(pores.mesh(4 * h, offset), pores.seeds(middle, 0.15), &middle);
    ASSERT_EQ(table.holes.size(), 12u);
    const double radius = IcosahedronPores::kRadius, mid = radius + shift * 4 * h;
    const double diameter = 2 * mid * std::sin(spot / radius);
    const double edge = 2 * mid * std::sin(std::atan(2.0) / 2);  // icosahedron: 63.4 degrees apart
    double worst_circularity = 1.0;
    for (std::size_t i = 0; i < 12; ++i) {
      const HoleRecord& r = table.holes[i];
      EXPECT_NEAR(r.diameter, diameter, 0.03 * diameter);
      EXPECT_NEAR((r.centre - pores.centre).norm(), mid, 0.02 * h);
      EXPECT_NEAR((r.centre - pores.centre).normalized().dot(pores.spots[i]), 1.0, 1e-4);
      EXPECT_NEAR(r.normal.dot(pores.spots[i]), 1.0, 1e-4);
      EXPECT_NEAR(r.nearest, edge, 0.01 * edge);
      worst_circularity = std::min(worst_circularity, r.circularity);
    }
    // The facets of marching tetrahedra make the rim a little jagged: about 0.5% off a circle.
    EXPECT_GT(worst_circularity, 0.98);
    std::printf("%s wall: diameter %.4f (circle %.4f), circularity %.3f - %.3f\n", to_string(offset).c_str(),
                table.holes[0].diameter, diameter, worst_circularity, table.holes[0].circularity);
  }
}

// Wide pores in a thin curved wall: 0.12 (0.4 rad) in a wall of 2 h. The tangent plane at the wall's
// middle leaves the wall 0.1 from the axis, inside every hole, and finds no loop; the cut along the
// wall's middle measures all 12.
TEST(HoleTable, TheCutFollowsACurvedWall) {
  const double spot = 0.12, h = IcosahedronPores::kH;
  const IcosahedronPores pores(spot);
  const TriangleMesh mesh = pores.mesh(2 * h, WallOffset::centered);
  const SurfaceMidWall middle(pores.sphere, h, 2 * h, WallOffset::centered, {});
  const std::vector<HoleSeed> seeds = pores.seeds(middle, 0.25);
  const HoleTable flat = measure_holes(mesh, seeds);
  EXPECT_EQ(flat.holes.size(), 0u);
  EXPECT_EQ(flat.dropped, 12u);
  const HoleTable table = measure_holes(mesh, seeds, &middle);
  ASSERT_EQ(table.holes.size(), 12u);
  const double diameter = 2 * IcosahedronPores::kRadius * std::sin(spot / IcosahedronPores::kRadius);
  for (const HoleRecord& r : table.holes) {
    EXPECT_NEAR(r.diameter, diameter, 0.03 * diameter);
    EXPECT_GT(r.circularity, 0.98);
    EXPECT_NEAR((r.centre - pores.centre).norm(), IcosahedronPores::kRadius, 0.1 * h);
  }
}

}  // namespace
}  // namespace poreshell
