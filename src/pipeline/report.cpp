#include "pipeline/report.hpp"

namespace poreshell {

nlohmann::json to_json(const PipelineResult& r) {
  using nlohmann::json;
  json meshes = json::array();
  for (const MeshOutput& m : r.meshes) {
    json hole_table = json::array();
    for (const HoleRecord& h : m.hole_table.holes)
      hole_table.push_back({{"centre", {h.centre.x(), h.centre.y(), h.centre.z()}},
                            {"normal", {h.normal.x(), h.normal.y(), h.normal.z()}},
                            {"diameter", h.diameter},
                            {"circularity", h.circularity},
                            {"nearest", h.nearest}});
    meshes.push_back(
        {{"iso", m.iso},
         {"path", m.path.string()},
         {"triangles", m.topology.triangles},
         {"vertices", m.topology.vertices},
         {"closed", m.topology.closed()},
         {"manifold", m.topology.manifold()},
         {"oriented", m.topology.oriented()},
         {"euler_characteristic", m.topology.euler_characteristic},
         {"volume", m.topology.signed_volume},
         {"min_angle_degrees", m.topology.min_angle_degrees},
         {"pores_from_euler", m.pores_from_euler},
         {"spots_at_iso", m.spots_at_iso},
         {"holes",
          {{"count", m.holes.holes.size()},
           {"diameter_mean_mm", m.holes.diameter_mean},
           {"diameter_cv", m.holes.diameter_cv},
           {"spacing_mean_mm", m.holes.spacing_mean},
           {"spacing_cv", m.holes.spacing_cv},
           {"porosity", m.holes.porosity}}},
         {"hole_table", hole_table},
         {"hole_table_dropped", m.hole_table.dropped},
         {"reduction", m.reduction ? nlohmann::json{{"triangles_before", m.reduction->triangles_before},
                                                    {"triangles_after", m.reduction->triangles_after},
                                                    {"max_distance_mm", m.reduction->max_distance},
                                                    {"reached_target", m.reduction->reached_target}}
                                   : nlohmann::json(nullptr)},
         {"wall",
          {{"requested_mm", r.solid.wall_mm},
           {"measured_median_mm", m.wall.median},
           {"measured_min_mm", m.wall.min},
           {"measured_max_mm", m.wall.max},
           {"probes", m.wall.probes}}}});
  }
  const double mm_per_grid = r.input.millimetres_per_unit / r.input.scale;
  json holes = json::object();
  if (r.plan)
    holes = {{"requested",
              {{"diameter_mm", r.requested_holes.diameter},
               {"spacing_mm", r.requested_holes.spacing},
               {"porosity", r.requested_holes.porosity}}},
             {"planned",
              {{"diameter_mm", r.plan->diameter},
               {"spacing_mm", r.plan->spacing},
               {"porosity", r.plan->porosity},
               {"pore_level", r.plan->level},
               {"voxel_size_mm", r.plan->voxel_size}}}};
  if (r.grading)
    holes["grading"] = {{"min_diameter_mm", r.grading->min_diameter},
                        {"max_diameter_mm", r.grading->max_diameter},
                        {"clamped_fraction", r.grading->clamped_fraction},
                        {"printable_min_mm", r.grading->clamped_min},
                        {"printable_max_mm", r.grading->clamped_max}};
  json mesh = meshes.empty() ? json::object() : meshes.front();
  mesh["outputs"] = meshes;
  mesh["unperforated_euler_characteristic"] = r.unperforated_euler;
  json energy_trace = json::array();
  for (const auto& [step, e] : r.run.energy_trace) energy_trace.push_back({step, e});
  json coarse_start = nullptr;  // no coarse start
  if (const auto& c = r.coarse_start)
    coarse_start = {{"grid", c->dims},
                    {"h_mm", c->h * mm_per_grid},
                    {"band_voxels", c->band_voxels},
                    {"steps", c->run.steps},
                    {"final_ec", c->run.final_ec},
                    {"reached_tolerance", c->run.reached_tolerance},
                    {"inner_iterations", c->run.inner_iterations},
                    {"repeated_steps", c->run.repeated_steps},
                    {"spots", c->spots},
                    {"seconds", c->seconds}};
  return {
      {"input",
       {{"kind", r.input.kind},
        {"name", r.input.name},
        {"vertices", r.input.vertices},
        {"triangles", r.input.triangles},
        {"boundary_edges", r.input.boundary_edges},
        {"dropped_degenerate", r.input.dropped_degenerate},
        {"euler_characteristic", r.input.euler_characteristic},
        {"scale_to_grid", r.input.scale},
        {"point_route", r.input.point_route},  // points only: direct | paper
        {"densified_points", r.input.densified_points},
        {"segmentation_iterations", r.input.segmentation_iterations}}},
      {"units",
       {{"input", r.input.units}, {"input_mm_per_unit", r.input.millimetres_per_unit}, {"output", "mm"}}},
      {"grid",
       {{"dims", r.grid_dims},
        {"h", r.h},
        {"h_input_units", r.h / r.input.scale},
        {"h_mm", r.h / r.input.scale * r.input.millimetres_per_unit}}},
      {"solid",
       {{"mode", r.solid.mode},
        {"wall_mm", r.solid.wall_mm},
        {"offset", r.solid.offset},
        {"spacing_mm", r.solid.spacing_mm},
        {"samples", r.solid.samples},
        {"incomplete_stencils", r.solid.incomplete_stencils},
        {"seconds_sample", r.solid.seconds_sample}}},
      {"band",
       {{"voxels", r.band_voxels},
        {"ghosts", r.ghosts},
        {"paper_ghosts", r.band_stats.paper_ghosts},
        {"closure_added", r.band_stats.closure_added},
        {"bytes", r.band_bytes}}},
      {"model",
       {{"alpha", r.model.alpha},
        {"epsilon", r.model.epsilon},
        {"phi_bar", r.model.phi_bar},
        {"dt", r.dt},
        {"alpha_per_mm2", r.model.alpha / (mm_per_grid * mm_per_grid)},
        {"epsilon_mm", r.model.epsilon * mm_per_grid},
        {"h_mm", r.h * mm_per_grid}}},
      {"holes", holes},
      {"solver",
       {{"name", r.solver_name},
        {"inner_iteration", r.inner_iteration},
        {"steps", r.run.steps},
        {"final_ec", r.run.final_ec},
        {"reached_tolerance", r.run.reached_tolerance},
        {"inner_converged", r.run.inner_converged},
        {"inner_iterations", r.run.inner_iterations},
        {"repeated_steps", r.run.repeated_steps},
        {"coarse_start", coarse_start},
        {"energy", {{"first", r.run.energy_first}, {"last", r.run.energy_last}, {"trace", energy_trace}}}}},
      {"pattern",
       {{"spots", r.spots.count},
        {"size_cv", r.spots.size_cv},
        {"mean_size_voxels", r.spots.mean_size},
        {"area_fraction", r.spots.area_fraction},
        {"spacing_mean_voxels", r.spots.spacing_mean},
        {"spacing_cv", r.spots.spacing_cv}}},
      {"mesh", mesh},
      {"memory",
       {{"band_bytes", r.band_bytes},
        {"solver_bytes", r.solver_bytes},
        {"peak_rss_after_band", r.peak_rss_after_band},
        {"peak_rss_after_solve", r.peak_rss_after_solve},
        {"peak_rss_total", r.peak_rss_total},
        {"peak_rss_after_solve_per_band_voxel",
         r.band_voxels ? static_cast<double>(r.peak_rss_after_solve) / static_cast<double>(r.band_voxels)
                       : 0.0}}},
      {"seconds",
       {{"input", r.seconds_input},
        {"band", r.seconds_band},
        {"solve", r.seconds_solve},
        {"mesh", r.seconds_mesh},
        {"total", r.seconds_total}}},
      {"threads", r.threads},
  };
}

}  // namespace poreshell
