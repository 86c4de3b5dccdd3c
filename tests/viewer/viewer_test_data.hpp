#pragma once
// Synthetic data for the viewer's tests: a sphere of radius 40 mm centred off the origin, with holes
// cut on a Fibonacci lattice (diameters 6 mm +- 20 %), a keep-out sphere and box, and a report. As a
// preview: the whole sphere with the holes painted on (a pattern value per vertex), holes without
// measured loops, and a preview's report (no solid: its figures are zeros).

#include <cmath>
#include <numbers>

#include "viewer/html_viewer.hpp"

namespace poreshell::testing {

inline constexpr double kFoldRadius = 37.0;  // the run page's second sheet (below)

inline ViewerData viewer_test_data(int holes = 40, bool preview = false) {
  ViewerData data;
  data.title = "Sphere <test> & holes";
  const Vec3 centre(10.0, -5.0, 20.0);
  const double radius = 40.0;
  const double pi = std::numbers::pi;
  for (int i = 0; i < holes; ++i) {  // Fibonacci lattice
    const double z = 1.0 - 2.0 * (i + 0.5) / holes;
    const double phi = i * pi * (3.0 - std::sqrt(5.0));
    const Vec3 n(std::sqrt(1.0 - z * z) * std::cos(phi), std::sqrt(1.0 - z * z) * std::sin(phi), z);
    ViewerHole h;
    h.centre = centre + radius * n;
    h.normal = n;
    h.diameter_mm = 6.0 * (1.0 + 0.2 * std::sin(1.7 * i));
    h.circularity = preview ? 0.0 : 0.9 + 0.1 * std::cos(i);
    h.axis_ratio = preview ? 0.0 : 0.8 + 0.2 * std::sin(0.3 * i);
    h.asked_mm = 5.0 + 0.05 * i;  // graded: each hole's own
    data.holes.push_back(h);
  }
  for (ViewerHole& h : data.holes) {
    h.nearest_neighbour_mm = 1e9;
    for (const ViewerHole& o : data.holes)
      if (&o != &h) h.nearest_neighbour_mm = std::min(h.nearest_neighbour_mm, (o.centre - h.centre).norm());
  }
  // UV spheres about `centre`, each triangle added where `keep` says.
  const int rings = 64, segments = 128;
  const auto add_sphere = [&](double r_sphere, const auto& keep) {
    const auto first = static_cast<std::int32_t>(data.mesh.vertices.size());
    for (int r = 0; r <= rings; ++r)
      for (int s = 0; s < segments; ++s) {
        const double theta = pi * r / rings, phi = 2.0 * pi * s / segments;
        data.mesh.vertices.push_back(centre + r_sphere * Vec3(std::sin(theta) * std::cos(phi),
                                                              std::sin(theta) * std::sin(phi),
                                                              std::cos(theta)));
      }
    const auto index = [&](int r, int s) { return first + r * segments + (s % segments); };
    for (int r = 0; r < rings; ++r)
      for (int s = 0; s < segments; ++s) {
        const std::array<std::int32_t, 3> a{index(r, s), index(r + 1, s), index(r + 1, s + 1)};
        const std::array<std::int32_t, 3> b{index(r, s), index(r + 1, s + 1), index(r, s + 1)};
        if (r > 0 && keep(a)) data.mesh.triangles.push_back(a);
        if (r + 1 < rings && keep(b)) data.mesh.triangles.push_back(b);
      }
  };
  // The sphere without the triangles inside a hole.
  add_sphere(radius, [&](const std::array<std::int32_t, 3>& t) {
    if (preview) return true;
    const Vec3 c = (data.mesh.vertices[t[0]] + data.mesh.vertices[t[1]] + data.mesh.vertices[t[2]]) / 3.0;
    for (const ViewerHole& h : data.holes)
      if ((c - h.centre).norm() < 0.5 * h.diameter_mm) return false;
    return true;
  });
  // A run's page also has a sheet 3 mm under the sphere, as where the surface folds over itself: within
  // every hole's reach of colour (1.3 radii), seen through each hole, and joined to none of them.
  if (!preview) add_sphere(kFoldRadius, [](const std::array<std::int32_t, 3>&) { return true; });
  if (preview)
    for (const Vec3& v : data.mesh.vertices) {
      double open = -1.0;
      for (const ViewerHole& h : data.holes)
        open = std::max(open, 0.5 * h.diameter_mm - (v - h.centre).norm());
      data.pattern.push_back(static_cast<float>(open));
    }
  data.requested_diameter_mm = 6.0;
  data.rim_width_mm = 2.0;
  data.keep_out_spheres.push_back({centre + Vec3(0.0, 0.0, radius), 8.0});
  data.keep_out_boxes.push_back({centre + Vec3(30.0, -10.0, -10.0), centre + Vec3(50.0, 10.0, 10.0)});
  double mean = 0.0, spacing = 0.0;
  for (const ViewerHole& h : data.holes) {
    mean += h.diameter_mm / holes;
    spacing += h.nearest_neighbour_mm / holes;
  }
  data.report = {
      {"holes", {{"requested", {{"diameter_mm", 6.0}, {"spacing_mm", 10.0}, {"porosity", nullptr}}}}},
      {"solid", {{"wall_mm", 2.0}}},
      {"mesh",
       {{"path", "out/sphere.stl"},
        {"applied", {{"rim_measured_mm", 2.74}, {"keep_out_clearance_mm", 1.83}, {"holes_in_keep_outs", 0}}},
        {"triangles", data.mesh.triangles.size()},
        {"volume", 4.0 / 3.0 * pi * (std::pow(radius + 1.0, 3) - std::pow(radius - 1.0, 3))},
        {"holes",
         {{"count", holes},
          {"diameter_mean_mm", mean},
          {"diameter_cv", 0.14},
          {"spacing_mean_mm", spacing},
          {"spacing_cv", 0.05},
          {"porosity", 0.012}}},
        {"wall",
         {{"requested_mm", 2.0},
          {"measured_median_mm", 2.01},
          {"measured_min_mm", 1.95},
          {"measured_max_mm", 6.08},
          {"measured_p5_mm", 1.97},
          {"measured_p95_mm", 2.04},
          {"probes", 256},
          {"merged_probes", 3}}},
        {"outputs", {{{"path", "out/sphere.stl"}}, {{"path", "out/sphere.3mf"}}}}}}};
  if (preview) {
    data.report["preview"] = true;
    data.report["settings"] = {{"wall", 0.0}, {"hole_diameter", 6.0}, {"spacing", 10.0}};
    nlohmann::json& mesh = data.report["mesh"];
    mesh["path"] = "out/sphere.ply";
    mesh["outputs"] = {{{"path", "out/sphere.ply"}}};
    mesh["triangles"] = 0;
    mesh["volume"] = 0.0;
    mesh["wall"] = {{"requested_mm", 2.0},
                    {"measured_median_mm", 0.0},
                    {"measured_min_mm", 0.0},
                    {"measured_max_mm", 0.0},
                    {"probes", 0}};
  }
  return data;
}

}  // namespace poreshell::testing
