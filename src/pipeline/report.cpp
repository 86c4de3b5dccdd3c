#include "pipeline/report.hpp"

#include <fmt/format.h>

#include "core/units.hpp"

namespace poreshell {
namespace {

LevelReport level_report(const MeshOutput& m) {
  LevelReport l;
  l.iso = m.iso;
  const MeshTopology& t = m.topology;
  l.topology = {t.vertices,   t.triangles,  t.euler_characteristic, t.components,       t.closed(),
                t.manifold(), t.oriented(), t.signed_volume,        t.min_angle_degrees};
  l.holes = {static_cast<std::int64_t>(m.holes.holes.size()),
             m.holes.diameter_mean,
             m.holes.diameter_cv,
             m.holes.spacing_mean,
             m.holes.spacing_cv,
             m.holes.porosity,
             m.holes.cell_area_cv};
  if (m.reduction)
    l.reduction = ReductionReport{m.reduction->triangles_before, m.reduction->triangles_after,
                                  m.reduction->max_distance,     m.reduction->reached_target,
                                  m.reduction->sampled.max(),    m.reduction->sampled.samples};
  l.wall = {m.wall.median,
            m.wall.min,
            m.wall.max,
            m.wall.low,
            m.wall.high,
            static_cast<std::int64_t>(m.wall.probes),
            static_cast<std::int64_t>(m.wall.merged)};
  l.parts = {m.topology.components,      m.parts.removed_fragments,    m.parts.removed_voids,
             m.parts.removed_wall_voids, m.parts.removed_volume,       m.parts.filled_cavities,
             m.parts.filled_volume,      m.parts.largest_filled_volume};
  l.spots_at_iso = m.spots_at_iso;
  l.pores_from_euler = m.pores_from_euler;
  l.hole_table_dropped = static_cast<std::int64_t>(m.hole_table.dropped);
  l.spots_at_open_edge = m.spots_at_open_edge;
  l.spots_not_through = static_cast<std::int64_t>(m.hole_table.uncut.size()) - m.spots_at_open_edge;
  l.spots_in_another_hole = l.hole_table_dropped - static_cast<std::int64_t>(m.hole_table.uncut.size());
  l.zones.rim_asked = m.zones.rim_asked;
  l.zones.rim = m.zones.rim;
  l.zones.keep_out_clearance = m.zones.keep_out_clearance;
  l.zones.holes_in_keep_outs = m.zones.holes_in_keep_outs;
  return l;
}

// What the designer should hear of: a rule that empties the model, a keep-out that keeps nothing, a
// reduction that was given up.
void add_warnings(const PipelineResult& r, const Options& options, Report& report) {
  const ZoneAreas& z = r.zone_areas;
  // Issue 51: a rule that empties the model is news, said with the share each rule keeps solid.
  const auto share = [&](double area) { return z.surface > 0.0 ? 100.0 * area / z.surface : 0.0; };
  if (report.plan)
    for (const LevelReport& l : report.outputs)
      if (l.holes.porosity < 0.6 * report.plan->porosity)
        report.warnings.push_back(fmt::format(
            "the holes open {:.1f}% of the surface against the {:.1f}% asked (under 60% of it): the solid "
            "zones "
            "keep {:.0f}% of the surface (thin parts {:.0f}%, creases {:.0f}%, rims {:.0f}%, keep-outs "
            "{:.0f}%); lower `thin_feature_ratio` or `crease_angle`, or narrow `rim`, to open more",
            100.0 * l.holes.porosity, 100.0 * report.plan->porosity, share(z.solid), share(z.thin),
            share(z.creases), share(z.rims), share(z.keep_outs)));
  // Issue 51: a keep-out that keeps none of the surface is most likely in another frame or unit. One
  // outside the model's bounds the estimate names before the run (estimate.cpp).
  const ZoneOptions zones = zone_options(options);
  for (std::size_t k = 0; k < z.each_keep_out.size(); ++k) {
    if (z.each_keep_out[k].area > 0.0 || z.each_keep_out[k].outside_bounds) continue;
    report.warnings.push_back(fmt::format(
        "{} keeps none of the model's surface, which comes no nearer than {} mm to it; give it in the "
        "input's frame, in mm, over the part to keep solid",
        keep_out_name(zones, k), readable(z.each_keep_out[k].gap_mm)));
  }
  for (const MeshOutput& m : r.meshes)
    if (!m.reduction_skipped.empty())
      report.warnings.push_back(fmt::format(
          "the output at iso {:g} is the full isosurface, {} triangles: its reduction within `max_deviation` "
          "failed a check ({}); `max_triangles` asks for a count, `max_deviation` 0 for the full mesh",
          m.iso, m.mesh.triangles.size(), m.reduction_skipped));
}

}  // namespace

Report make_report(const PipelineResult& r, const Options& options) {
  Report report;
  report.version = PORESHELL_VERSION;
  report.settings = options;
  const InputSummary& in = r.input;
  report.input = {in.kind,
                  in.name,
                  in.vertices,
                  in.triangles,
                  in.boundary_edges,
                  in.dropped_degenerate,
                  in.euler_characteristic,
                  in.scale,
                  in.units,
                  in.millimetres_per_unit,
                  in.point_route,
                  in.densified_points,
                  in.segmentation_iterations,
                  in.thin_vertices,
                  in.crease_edges,
                  in.dropped_duplicate};
  const double mm_per_grid = in.millimetres_per_unit / in.scale;
  report.grid_dims = r.grid_dims;
  report.h = r.h;
  report.h_mm = r.h * mm_per_grid;
  report.solid = {r.solid.mode,
                  r.solid.offset,
                  r.solid.wall_mm,
                  r.solid.spacing_mm,
                  r.solid.seconds_sample,
                  static_cast<std::int64_t>(r.solid.samples),
                  r.solid.incomplete_stencils,
                  r.solid.wall_source};
  report.band = {static_cast<std::int64_t>(r.band_voxels), static_cast<std::int64_t>(r.ghosts),
                 r.band_stats.paper_ghosts, r.band_stats.closure_added,
                 static_cast<std::int64_t>(r.band_bytes)};
  report.model = {r.solve.model.alpha, r.solve.model.epsilon, r.solve.model.phi_bar, r.solve.dt,
                  uniform_state_unstable(r.solve.model.alpha, r.solve.model.epsilon, r.solve.model.phi_bar)};
  report.requested = {r.requested_holes.diameter, r.requested_holes.spacing, r.requested_holes.porosity};
  if (r.plan)
    report.plan = Report::Plan{r.plan->diameter,   r.plan->spacing, r.plan->porosity, r.plan->level,
                               r.plan->voxel_size, r.plan->alpha,   r.plan->epsilon,  r.plan->phi_bar};
  if (r.grading)
    report.grading =
        Report::Grading{r.grading->min_diameter, r.grading->max_diameter, r.grading->clamped_fraction,
                        r.grading->clamped_min, r.grading->clamped_max};
  auto& s = report.solver;
  s.name = r.solve.solver_name;
  s.inner_iteration = r.solve.inner_iteration;
  s.steps = r.solve.run.steps;
  s.inner_iterations = r.solve.run.inner_iterations;
  s.repeated_steps = r.solve.run.repeated_steps;
  s.final_ec = r.solve.run.final_ec;
  s.tolerance = options.tolerance;
  s.reached_tolerance = r.solve.run.reached_tolerance;
  s.stop_rule = r.solve.stop_rule == StopRule::holes ? "holes" : "paper";
  s.layout = r.solve.layout == Layout::cvt ? "cvt" : "paper";
  s.layout_holes = r.solve.layout_holes;
  report.preview = options.preview;
  s.inner_converged = r.solve.run.inner_converged;
  if (const auto& c = r.solve.coarse_start)
    s.coarse_start = Report::CoarseStart{c->dims,
                                         c->h * mm_per_grid,
                                         c->h,
                                         c->run.final_ec,
                                         c->seconds,
                                         static_cast<std::int64_t>(c->band_voxels),
                                         c->run.steps,
                                         c->run.inner_iterations,
                                         c->run.repeated_steps,
                                         c->spots,
                                         c->run.reached_tolerance};
  s.energy_first = r.solve.run.energy_first;
  s.energy_last = r.solve.run.energy_last;
  s.energy_trace = r.solve.run.energy_trace;
  report.pattern = {r.spots.count,          r.closed_small_holes, r.spots.size_cv,    r.spots.mean_size,
                    r.spots.area_fraction,  r.spots.spacing_mean, r.spots.spacing_cv, r.closed_oblong_holes,
                    r.rounded_oblong_holes, r.closed_rim_holes};
  for (const MeshOutput& m : r.meshes) report.outputs.push_back(level_report(m));
  const ZoneAreas& z = r.zone_areas;
  report.solid_zones = {z.surface, z.thin, z.creases, z.rims, z.keep_outs, z.solid};
  add_warnings(r, options, report);
  report.unperforated_euler_characteristic = r.unperforated_euler;
  report.memory = {static_cast<std::int64_t>(r.band_bytes), static_cast<std::int64_t>(r.solve.solver_bytes),
                   static_cast<std::int64_t>(r.peak_rss_after_band),
                   static_cast<std::int64_t>(r.peak_rss_after_solve),
                   static_cast<std::int64_t>(r.peak_rss_total)};
  report.seconds = {r.seconds_input, r.seconds_band, r.seconds_solve, r.seconds_mesh, r.seconds_total};
  report.threads = r.threads;
  return report;
}

}  // namespace poreshell
