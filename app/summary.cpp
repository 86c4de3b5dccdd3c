#include "summary.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli_support.hpp"

namespace {

std::string yes_no(bool b, const char* yes, const char* no) {
  return b ? yes : no;
}

// Why some of the band's spots have no hole in the hole table (issue 51), when any have none.
std::string spots_without_pore(const poreshell::LevelReport& m) {
  std::string parts;
  const auto add = [&](std::int64_t n, const char* what) {
    if (n > 0) parts += fmt::format("{}{} {}", parts.empty() ? "" : ", ", n, what);
  };
  add(m.spots_at_open_edge, "at the open edge (notches)");
  add(m.spots_not_through, "elsewhere (not cut through, or not measurable)");
  add(m.spots_in_another_hole, "inside another's hole");
  return parts.empty() ? std::string() : " (spots with no measured hole: " + parts + ")";
}

// 3 significant digits, whole numbers from 100 up, no exponent (issue 47: "1.11e+03 MB").
std::string readable(double x) {
  if (!std::isfinite(x) || std::abs(x) >= 1e15) return fmt::format("{:.3g}", x);
  return std::abs(x) >= 100.0 ? fmt::format("{:.0f}", x) : fmt::format("{:.3g}", x);
}

// Input, grid, band and model, and how the pattern was started.
void print_setup(const poreshell::Options& c, const poreshell::Report& r) {
  const auto& d = r.grid_dims;
  if (r.input.kind == "mesh")
    fmt::print(
        "  input    {} vertices, {} triangles ({} degenerate and {} repeated dropped), {} boundary edges, "
        "{:.2f} s\n",
        r.input.vertices, r.input.triangles, r.input.dropped_degenerate, r.input.dropped_duplicate,
        r.input.boundary_edges, r.seconds.input);
  if (r.input.kind == "points" && r.input.point_route == "paper")
    fmt::print("  input    {} points, route paper: {} after densification, {} steps of eq. (3.3), {:.2f} s\n",
               r.input.vertices, r.input.densified_points, r.input.segmentation_iterations, r.seconds.input);
  else if (r.input.kind == "points")
    fmt::print("  input    {} points, route direct (splats), {:.2f} s\n", r.input.vertices, r.seconds.input);
  fmt::print("  grid     {} x {} x {}, h = {:.6g} ({:.6g} mm; input coordinates in {}, output in mm)\n", d[0],
             d[1], d[2], r.h, r.h_mm, r.input.units);
  fmt::print("  band     {} voxels, {} ghosts, {:.1f} MiB\n", r.band.voxels, r.band.ghosts,
             static_cast<double>(r.band.bytes) / (1024.0 * 1024.0));
  if (r.plan)
    fmt::print(
        "  model    alpha {:g}, epsilon {:.6g} ({:.3g} h), phi-bar {:g}, dt {:.6g} ({:g} epsilon^2): the "
        "hole map\n",
        r.model.alpha, r.model.epsilon, r.model.epsilon / r.h, r.model.phi_bar, r.model.dt,
        r.model.dt / (r.model.epsilon * r.model.epsilon));
  else
    fmt::print("  model    alpha {:g}, epsilon {:.6g} (m = {:g}), phi-bar {:g}, dt {:.6g} ({:g} h)\n",
               r.model.alpha, r.model.epsilon, c.epsilon_m, r.model.phi_bar, r.model.dt, c.dt_h);
  if (const auto& cs = r.solver.coarse_start)
    fmt::print(
        "  coarse   pattern formed on {} x {} x {} (epsilon {:.3g} h there, {} band voxels): {} steps, "
        "{} inner iterations, {} spots, {:.2f} s; carried here\n",
        cs->grid[0], cs->grid[1], cs->grid[2], r.model.epsilon / cs->h, cs->band_voxels, cs->steps,
        cs->inner_iterations, cs->spots, cs->seconds);
  if (r.solver.layout == "cvt")
    fmt::print("  layout   cvt: {} discs at a centroidal Voronoi tessellation of the free surface{}\n",
               r.solver.layout_holes,
               r.solver.steps == 0 ? " (the preview's holes; the equation not run)" : "");
}

// How the equation ran and the pattern it formed.
void print_solve(const poreshell::Options& c, const poreshell::Report& r) {
  if (r.solver.steps == 0) {
    // A preview of the even layout: nothing was solved.
  } else if (r.solver.stop_rule == "holes")
    fmt::print(
        "  solver   {} ({} inner): {} steps, hole layout {} (holes rule), final e_c {:.3e}, {} inner "
        "iterations{}\n",
        r.solver.name, r.solver.inner_iteration, r.solver.steps,
        yes_no(r.solver.reached_tolerance, "settled", "NOT settled"), r.solver.final_ec,
        r.solver.inner_iterations, r.solver.inner_converged ? "" : " (some steps did not reach --inner-tol)");
  else
    fmt::print(
        "  solver   {} ({} inner): {} steps, final e_c {:.3e} {} tol {:g} ({}), {} inner iterations{}\n",
        r.solver.name, r.solver.inner_iteration, r.solver.steps, r.solver.final_ec,
        r.solver.reached_tolerance ? "<" : ">=", c.tolerance,
        yes_no(r.solver.reached_tolerance, "reached", "NOT reached"), r.solver.inner_iterations,
        r.solver.inner_converged ? "" : " (some steps did not reach --inner-tol)");
  if (std::isnan(r.solver.energy_first))
    fmt::print("  energy   not evaluated (a diagnostic: --energy-every K)\n");
  else
    fmt::print("  energy   first {:.6e}, final {:.6e}\n", r.solver.energy_first, r.solver.energy_last);
  fmt::print(
      "  pattern  {} spots at phi > 0, size CV {:.3f}, spacing {:.2f} h (CV {:.3f}), area fraction {:.3f}\n",
      r.pattern.spots, r.pattern.size_cv, r.pattern.spacing_mean_voxels, r.pattern.spacing_cv,
      r.pattern.area_fraction);
  const char* plural = r.pattern.closed_small_holes == 1 ? "" : "s";
  if (r.pattern.closed_small_holes > 0 && r.preview && r.solver.steps == 0)
    fmt::print("  closed   {} disc{} under 0.915 of the asked diameter (the run would close {})\n",
               r.pattern.closed_small_holes, plural, r.pattern.closed_small_holes == 1 ? "it" : "them");
  else if (r.pattern.closed_small_holes > 0)
    fmt::print("  closed   {} hole{} under 0.7 of the asked diameter (pinholes next to solid zones)\n",
               r.pattern.closed_small_holes, plural);
  if (r.pattern.closed_oblong_holes > 0)
    fmt::print(
        "  closed   {} oblong hole{} (axis ratio under 0.8 on the surface, too narrow to round: slots "
        "beside solid zones, creases or tight bends)\n",
        r.pattern.closed_oblong_holes, r.pattern.closed_oblong_holes == 1 ? "" : "s");
  if (r.pattern.rounded_oblong_holes > 0)
    fmt::print(
        "  rounded  {} oblong hole{} (axis ratio under 0.8 on the surface): cut to a disc about {} centre\n",
        r.pattern.rounded_oblong_holes, r.pattern.rounded_oblong_holes == 1 ? "" : "s",
        r.pattern.rounded_oblong_holes == 1 ? "its" : "their");
  if (r.pattern.closed_rim_holes > 0)
    fmt::print("  closed   {} hole{} that would leave less than the rim asked\n", r.pattern.closed_rim_holes,
               r.pattern.closed_rim_holes == 1 ? "" : "s");
}

// Time and memory, the solid, its zones and the hole map.
void print_cost_and_solid(const poreshell::Report& r) {
  fmt::print("  time     band {:.2f} s, solve {:.2f} s, mesh+write {:.2f} s, total {:.2f} s ({} threads)\n",
             r.seconds.band, r.seconds.solve, r.seconds.mesh, r.seconds.total, r.threads);
  constexpr double kMiB = 1024.0 * 1024.0;
  fmt::print(
      "  memory   peak {:.0f} MiB after the band, {:.0f} MiB after the solve ({:.0f} B per band voxel), "
      "{:.0f} MiB "
      "in all\n",
      static_cast<double>(r.memory.peak_rss_after_band) / kMiB,
      static_cast<double>(r.memory.peak_rss_after_solve) / kMiB,
      r.band.voxels ? static_cast<double>(r.memory.peak_rss_after_solve) / static_cast<double>(r.band.voxels)
                    : 0.0,
      static_cast<double>(r.memory.peak_rss_total) / kMiB);
  if (r.preview)
    fmt::print("  solid    none (a preview: the surface with its holes painted on)\n");
  else if (r.solid.mode == "shell")
    fmt::print("  solid    shell, wall {:.4g} mm{} {}, meshed at {:.4g} mm ({} samples, {:.2f} s)\n",
               r.solid.wall_mm,
               r.solid.wall_source == "default"
                   ? " (the default for holes in mm; --wall to change)"
                   : (r.solid.wall_source == "band" ? " (the band's width 2 delta; --wall to change)" : ""),
               r.solid.offset, r.solid.spacing_mm, r.solid.samples, r.solid.seconds_sample);
  else
    fmt::print("  solid    narrow volume (Fig. 3b), {:.4g} mm thick (2 delta)\n", r.solid.wall_mm);
  if (const auto& z = r.solid_zones; z.solid > 0.0)
    fmt::print(
        "  zones    {:.0f}% of the surface kept solid: thin parts {:.0f}%, creases {:.0f}%, rims {:.0f}%, "
        "keep-outs {:.0f}%\n",
        100.0 * z.solid / z.surface, 100.0 * z.thin / z.surface, 100.0 * z.creases / z.surface,
        100.0 * z.rims / z.surface, 100.0 * z.keep_outs / z.surface);
  if (r.plan)
    fmt::print(
        "  holes    asked {:.4g} mm at {:.4g} mm spacing: alpha {:.4g} /mm^2, epsilon {:.4g} mm, phi-bar "
        "{:g}, "
        "h {:.4g} mm, pore level {:.3f}\n",
        r.plan->diameter, r.plan->spacing, r.plan->alpha_per_mm2, r.plan->epsilon_mm, r.plan->phi_bar, r.h_mm,
        r.plan->pore_level);
  if (r.grading)
    fmt::print(
        "  grading  diameters {:.3g} to {:.3g} mm asked; {:.1f}% of the surface clamped to {:.3g}-{:.3g} "
        "mm\n",
        r.grading->min_diameter, r.grading->max_diameter, 100.0 * r.grading->clamped_fraction,
        r.grading->printable_min, r.grading->printable_max);
}

// One pore level's measures and file; `output` (its mesh and hole table) may be null.
void print_level(const poreshell::Options& c, const poreshell::Report& r, const poreshell::LevelReport& m,
                 const poreshell::Output* output) {
  const auto& t = m.topology;
  fmt::print(
      "  measured {} holes, diameter {:.4g} mm (CV {:.3f}), spacing {:.4g} mm (CV {:.3f}), porosity {:.3f}",
      m.holes.count, m.holes.diameter_mean, m.holes.diameter_cv, m.holes.spacing_mean, m.holes.spacing_cv,
      m.holes.porosity);
  if (m.reduction)
    fmt::print("; reduced {} -> {} triangles, within {:.3g} mm of the full isosurface (checked at {} points)",
               m.reduction->triangles_before, m.reduction->triangles_after, m.reduction->max_distance,
               m.reduction->sampled_points);
  if (m.parts.removed_fragments + m.parts.removed_voids > 0)
    fmt::print("; removed {} specks and {} sealed voids ({:.3g} mm^3{})", m.parts.removed_fragments,
               m.parts.removed_voids, m.parts.removed_volume,
               m.parts.removed_wall_voids > 0
                   ? fmt::format(", {} of them in the wall without pores too", m.parts.removed_wall_voids)
                   : "");
  if (m.parts.filled_cavities > 0)
    fmt::print("; filled {} sealed cavities no pore opens ({:.3g} mm^3, the largest {:.3g})",
               m.parts.filled_cavities, m.parts.filled_volume, m.parts.largest_filled_volume);
  if (m.parts.parts > 1) fmt::print("; {} separate parts", m.parts.parts);
  if (m.wall.probes > 0) {
    fmt::print("; wall {:.4g} mm ({:.4g}-{:.4g} over 90% of {} probes", m.wall.median, m.wall.low,
               m.wall.high, m.wall.probes);
    if (m.wall.merged > 0)
      fmt::print(", {} up to {:.4g} mm where the part is thinner than two walls and solid", m.wall.merged,
                 m.wall.max);
    fmt::print(")");
  }
  fmt::print("\n");
  if (output && !output->holes.empty() && !r.preview) {
    double circularity = 0.0, diameter = 0.0, least_diameter = 1e300, least_axis_ratio = 1.0;
    for (const poreshell::Hole& h : output->holes) {
      circularity += h.circularity;
      diameter += h.diameter;
      least_diameter = std::min(least_diameter, h.diameter);
      least_axis_ratio = std::min(least_axis_ratio, h.axis_ratio);
    }
    const auto n = static_cast<double>(output->holes.size());
    fmt::print("  on mesh  {} holes at mid-wall, diameter {:.4g} mm (least {:.3g}), circularity {:.3f}, ",
               output->holes.size(), diameter / n, least_diameter, circularity / n);
    fmt::print("least axis ratio {:.2f}\n", least_axis_ratio);
  }
  // What the zones asked for, as measured on the holes.
  if (m.zones.rim_asked > 0.0 && !std::isnan(m.zones.rim))
    fmt::print("  rim      {:.3g} mm from the open boundary to the nearest hole (asked {:g} mm{})\n",
               m.zones.rim, m.zones.rim_asked, std::isnan(c.rim) ? ", the default: half a hole" : "");
  if (!std::isnan(m.zones.keep_out_clearance))
    fmt::print("  keep-out {} zones, {}; nearest hole edge {:.3g} mm from one\n",
               c.keep_out.size() + c.keep_out_boxes.size(),
               m.zones.holes_in_keep_outs == 0 ? std::string("no hole reaches in")
                                               : fmt::format("{} HOLES REACH IN", m.zones.holes_in_keep_outs),
               m.zones.keep_out_clearance);
  const std::string path = m.path.empty() ? std::string("no file (no -o)") : m.path;
  if (r.preview) {
    fmt::print("  output   {} (iso {:g}): the surface with {} holes painted on (preview)\n", path, m.iso,
               m.holes.count);
    return;
  }
  fmt::print(
      "  output   {} (iso {:g}): {} triangles, {}, {}, smallest angle {:.1f} deg, Euler characteristic {}, "
      "pores from Euler {} vs {} spots on band{}\n",
      path, m.iso, t.triangles, yes_no(t.closed, "closed", "OPEN"),
      yes_no(t.manifold, "manifold", "NON-MANIFOLD"), t.min_angle_degrees, t.euler_characteristic,
      m.pores_from_euler, m.spots_at_iso, spots_without_pore(m));
}

}  // namespace

void print_estimate(const std::string& input_name, const poreshell::Estimate& e) {
  fmt::print("poreshell {}: {}\n", poreshell::version(), input_name);
  fmt::print("  size     {:.4g} x {:.4g} x {:.4g} mm\n", e.size_mm[0], e.size_mm[1], e.size_mm[2]);
  const std::string time = e.seconds < 10.0   ? fmt::format("{:.1f} s", e.seconds)
                           : e.seconds < 90.0 ? fmt::format("{:.0f} s", e.seconds)
                                              : fmt::format("{:.1f} min", e.seconds / 60.0);
  const std::string output =
      e.preview ? fmt::format("the surface painted, {} MB as PLY ({} million triangles; preview)",
                              readable(e.ply_bytes / 1e6), readable(e.triangles / 1e6))
                : fmt::format("{} MB as STL ({} million triangles)", readable(e.stl_bytes / 1e6),
                              readable(e.triangles / 1e6));
  fmt::print(
      "  estimate about {:.3g} million band voxels on {} x {} x {} (h = {:.3g} mm): about {} on 2 cores, "
      "peak memory {:.0f} MiB, output {}\n",
      e.band_voxels / 1e6, e.grid[0], e.grid[1], e.grid[2], e.voxel_size_mm, time,
      e.peak_bytes / (1024.0 * 1024.0), output);
  for (const std::string& warning : e.warnings) fmt::print("  warning  {}\n", warning);
  std::fflush(stdout);
}

void print_summary(const poreshell::Options& c, const poreshell::Report& r,
                   std::span<const poreshell::Output> outputs, const std::string& report,
                   std::span<const WrittenFile> others) {
  print_setup(c, r);
  print_solve(c, r);
  print_cost_and_solid(r);
  for (std::size_t i = 0; i < r.outputs.size(); ++i)
    print_level(c, r, r.outputs[i], i < outputs.size() ? &outputs[i] : nullptr);
  if (!report.empty()) fmt::print("  report   {}\n", report);
  std::string also;
  for (const WrittenFile& f : others)
    if (!f.path.empty()) also += (also.empty() ? "" : ", ") + f.path + " (" + f.what + ")";
  if (!also.empty()) fmt::print("  also     {}\n", also);
}

void print_warnings(const poreshell::Options& c, const poreshell::Report& r) {
  for (const std::string& warning : r.warnings)
    fmt::print(stderr, "poreshell: warning: {}\n", with_flags(warning));
  if (r.solver.steps == 0) {
    // Nothing solved (a preview of the even layout): no stop to warn about.
  } else if (!r.solver.reached_tolerance && r.solver.stop_rule == "holes")
    fmt::print(
        stderr,
        "poreshell: warning: stopped at --max-steps {} before the hole layout settled; raise --max-steps\n",
        r.solver.steps);
  else if (!r.solver.reached_tolerance)
    fmt::print(
        stderr,
        "poreshell: warning: stopped at --max-steps {} with e_c = {:.3e} above --tol {:g}; the pattern may "
        "not be steady yet, raise --max-steps\n",
        r.solver.steps, r.solver.final_ec, c.tolerance);
  if (!r.solver.inner_converged)
    fmt::print(
        stderr,
        "poreshell: warning: some steps did not reach --inner-tol {:g}; the result may be inaccurate\n",
        c.inner_tolerance);
  if (r.grading && r.grading->clamped_fraction > 0.0 && r.plan)
    fmt::print(
        stderr,
        "poreshell: warning: the grading asked for holes from {:.3g} to {:.3g} mm; at {:.3g} mm spacing "
        "they were clamped to {:.3g}-{:.3g} mm on {:.1f}% of the surface (wider holes would merge, "
        "narrower ones close)\n",
        r.grading->min_diameter, r.grading->max_diameter, r.plan->spacing, r.grading->printable_min,
        r.grading->printable_max, 100.0 * r.grading->clamped_fraction);
  if (!r.model.pattern_can_form) {
    const double a = 1.0 - 3.0 * r.model.phi_bar * r.model.phi_bar;
    const double eps = r.model.epsilon;
    fmt::print(stderr,
               "poreshell: warning: no pattern can form: the uniform state is stable for alpha {:g}, epsilon "
               "{:.4g}, phi-bar {:g} (needs 4 alpha eps^2 < (1 - 3 phi_bar^2)^2); use --alpha below {:.4g}\n",
               r.model.alpha, eps, r.model.phi_bar, a > 0 ? a * a / (4 * eps * eps) : 0.0);
  }
}
