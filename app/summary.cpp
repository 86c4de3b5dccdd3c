#include "summary.hpp"

#include <fmt/core.h>

#include <cmath>
#include <cstdio>

namespace {

std::string yes_no(bool b, const char* yes, const char* no) {
  return b ? yes : no;
}

}  // namespace

void print_progress(const poreshell::StepProgress& p, std::chrono::steady_clock::time_point start) {
  if (p.step != 1 && p.step % 10 != 0 && std::isnan(p.energy)) return;
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::string line = fmt::format("{}step {:5d}  e_c {:.3e}", p.coarse ? "coarse " : "", p.step, p.ec);
  if (!std::isnan(p.energy)) line += fmt::format("  energy {:.6e}", p.energy);
  line += fmt::format("  inner {} iterations{}  {:.1f} s", p.inner.inner_iterations,
                      p.inner.converged ? "" : " (not converged)", t);
  fmt::print(stderr, "{}\n", line);
}

void print_summary(const poreshell::PipelineConfig& c, const poreshell::PipelineResult& r,
                   const std::string& report) {
  const auto& d = r.grid_dims;
  fmt::print("poreshell {}: {}\n", PORESHELL_VERSION, r.input.name);
  if (r.input.kind == "mesh")
    fmt::print("  input    {} vertices, {} triangles ({} degenerate dropped), {} boundary edges, {:.2f} s\n",
               r.input.vertices, r.input.triangles, r.input.dropped_degenerate, r.input.boundary_edges,
               r.seconds_input);
  if (r.input.kind == "points" && r.input.point_route == "paper")
    fmt::print("  input    {} points, route paper: {} after densification, {} steps of eq. (3.3), {:.2f} s\n",
               r.input.vertices, r.input.densified_points, r.input.segmentation_iterations, r.seconds_input);
  else if (r.input.kind == "points")
    fmt::print("  input    {} points, route direct (splats), {:.2f} s\n", r.input.vertices, r.seconds_input);
  fmt::print("  grid     {} x {} x {}, h = {:.6g} ({:.6g} mm; input coordinates in {}, output in mm)\n", d[0],
             d[1], d[2], r.h, r.h / r.input.scale * r.input.millimetres_per_unit, r.input.units);
  fmt::print("  band     {} voxels, {} ghosts, {:.1f} MiB\n", r.band_voxels, r.ghosts,
             static_cast<double>(r.band_bytes) / (1024.0 * 1024.0));
  if (r.plan)
    fmt::print(
        "  model    alpha {:g}, epsilon {:.6g} ({:.3g} h), phi-bar {:g}, dt {:.6g} ({:g} epsilon^2): the "
        "hole map\n",
        r.model.alpha, r.model.epsilon, r.model.epsilon / r.h, r.model.phi_bar, r.dt,
        r.dt / (r.model.epsilon * r.model.epsilon));
  else
    fmt::print("  model    alpha {:g}, epsilon {:.6g} (m = {:g}), phi-bar {:g}, dt {:.6g} ({:g} h)\n",
               r.model.alpha, r.model.epsilon, c.epsilon_m, r.model.phi_bar, r.dt, c.dt_in_h);
  if (const auto& cs = r.coarse_start)
    fmt::print(
        "  coarse   pattern formed on {} x {} x {} (epsilon {:.3g} h there, {} band voxels): {} steps, "
        "{} inner iterations, {} spots, {:.2f} s; carried here\n",
        cs->dims[0], cs->dims[1], cs->dims[2], r.model.epsilon / cs->h, cs->band_voxels, cs->run.steps,
        cs->run.inner_iterations, cs->spots, cs->seconds);
  fmt::print("  solver   {} ({} inner): {} steps, final e_c {:.3e} {} tol {:g} ({}), {} inner iterations{}\n",
             r.solver_name, r.inner_iteration, r.run.steps, r.run.final_ec,
             r.run.reached_tolerance ? "<" : ">=", c.tolerance,
             yes_no(r.run.reached_tolerance, "reached", "NOT reached"), r.run.inner_iterations,
             r.run.inner_converged ? "" : " (some steps did not reach --inner-tol)");
  if (std::isnan(r.run.energy_first))
    fmt::print("  energy   not evaluated (a diagnostic: --energy-every K)\n");
  else
    fmt::print("  energy   first {:.6e}, final {:.6e}\n", r.run.energy_first, r.run.energy_last);
  fmt::print(
      "  pattern  {} spots at phi > 0, size CV {:.3f}, spacing {:.2f} h (CV {:.3f}), area fraction {:.3f}\n",
      r.spots.count, r.spots.size_cv, r.spots.spacing_mean, r.spots.spacing_cv, r.spots.area_fraction);
  fmt::print("  time     band {:.2f} s, solve {:.2f} s, mesh+write {:.2f} s, total {:.2f} s ({} threads)\n",
             r.seconds_band, r.seconds_solve, r.seconds_mesh, r.seconds_total, r.threads);
  constexpr double kMiB = 1024.0 * 1024.0;
  fmt::print(
      "  memory   peak {:.0f} MiB after the band, {:.0f} MiB after the solve ({:.0f} B per band voxel), "
      "{:.0f} MiB "
      "in all\n",
      static_cast<double>(r.peak_rss_after_band) / kMiB, static_cast<double>(r.peak_rss_after_solve) / kMiB,
      r.band_voxels ? static_cast<double>(r.peak_rss_after_solve) / static_cast<double>(r.band_voxels) : 0.0,
      static_cast<double>(r.peak_rss_total) / kMiB);
  if (r.solid.mode == "shell")
    fmt::print("  solid    shell, wall {:.4g} mm {}, meshed at {:.4g} mm ({} samples, {:.2f} s)\n",
               r.solid.wall_mm, r.solid.offset, r.solid.spacing_mm, r.solid.samples, r.solid.seconds_sample);
  else
    fmt::print("  solid    narrow volume (Fig. 3b), {:.4g} mm thick (2 delta)\n", r.solid.wall_mm);
  if (r.plan)
    fmt::print(
        "  holes    asked {:.4g} mm at {:.4g} mm spacing: alpha {:.4g} /mm^2, epsilon {:.4g} mm, phi-bar "
        "{:g}, "
        "h {:.4g} mm, pore level {:.3f}\n",
        r.plan->diameter, r.plan->spacing, r.plan->alpha, r.plan->epsilon, r.plan->phi_bar,
        r.h * r.input.millimetres_per_unit / r.input.scale, r.plan->level);
  if (r.grading)
    fmt::print(
        "  grading  diameters {:.3g} to {:.3g} mm asked; {:.1f}% of the surface clamped to {:.3g}-{:.3g} "
        "mm\n",
        r.grading->min_diameter, r.grading->max_diameter, 100.0 * r.grading->clamped_fraction,
        r.grading->clamped_min, r.grading->clamped_max);
  for (const poreshell::MeshOutput& m : r.meshes) {
    const auto& t = m.topology;
    fmt::print(
        "  measured {} holes, diameter {:.4g} mm (CV {:.3f}), spacing {:.4g} mm (CV {:.3f}), porosity {:.3f}",
        m.holes.holes.size(), m.holes.diameter_mean, m.holes.diameter_cv, m.holes.spacing_mean,
        m.holes.spacing_cv, m.holes.porosity);
    if (m.reduction)
      fmt::print("; reduced {} -> {} triangles, {:.3g} mm from the meshed surface{}",
                 m.reduction->triangles_before, m.reduction->triangles_after, m.reduction->max_distance,
                 m.reduction->reached_target ? "" : " (the deviation bound stopped it)");
    if (m.wall.probes > 0)
      fmt::print("; wall {:.4g} mm ({:.4g}-{:.4g}, {} probes)", m.wall.median, m.wall.min, m.wall.max,
                 m.wall.probes);
    fmt::print("\n");
    fmt::print(
        "  output   {} (iso {:g}): {} triangles, {}, {}, smallest angle {:.1f} deg, Euler characteristic {}, "
        "pores from Euler {} vs {} spots on band\n",
        m.path.string(), m.iso, t.triangles, yes_no(t.closed(), "closed", "OPEN"),
        yes_no(t.manifold(), "manifold", "NON-MANIFOLD"), t.min_angle_degrees, t.euler_characteristic,
        m.pores_from_euler, m.spots_at_iso);
  }
  if (!report.empty()) fmt::print("  report   {}\n", report);
}
