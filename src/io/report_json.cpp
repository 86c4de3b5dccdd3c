#include "io/report_json.hpp"

#include <cmath>

#include "io/option_json.hpp"

namespace poreshell {
namespace {

using nlohmann::json;

// NaN is not JSON: an energy never evaluated is null.
json number_or_null(double x) {
  return std::isnan(x) ? json(nullptr) : json(x);
}

json level_json(const LevelReport& m, const Report& r) {
  const TopologyReport& t = m.topology;
  return {{"iso", m.iso},
          {"path", m.path},
          {"triangles", t.triangles},
          {"vertices", t.vertices},
          {"closed", t.closed},
          {"manifold", t.manifold},
          {"oriented", t.oriented},
          {"components", t.components},
          {"euler_characteristic", t.euler_characteristic},
          {"volume", t.volume},
          {"min_angle_degrees", t.min_angle_degrees},
          {"pores_from_euler", m.pores_from_euler},
          {"parts",
           {{"count", m.parts.parts},
            {"removed_fragments", m.parts.removed_fragments},
            {"removed_voids", m.parts.removed_voids},
            {"removed_wall_voids", m.parts.removed_wall_voids},
            {"removed_volume_mm3", m.parts.removed_volume},
            {"filled_cavities", m.parts.filled_cavities},
            {"filled_volume_mm3", m.parts.filled_volume},
            {"largest_filled_volume_mm3", m.parts.largest_filled_volume}}},
          {"spots_at_iso", m.spots_at_iso},
          {"hole_table_dropped", m.hole_table_dropped},
          {"spots_without_pore",
           {{"at_open_edge", m.spots_at_open_edge},
            {"elsewhere", m.spots_not_through},
            {"in_another_hole", m.spots_in_another_hole}}},
          {"applied",
           {{"rim_requested_mm", m.zones.rim_asked},
            {"rim_measured_mm", number_or_null(m.zones.rim)},
            {"keep_outs", r.settings.keep_out.size() + r.settings.keep_out_boxes.size()},
            {"keep_out_clearance_mm", number_or_null(m.zones.keep_out_clearance)},
            {"holes_in_keep_outs", m.zones.holes_in_keep_outs}}},
          {"holes",
           {{"count", m.holes.count},
            {"diameter_mean_mm", m.holes.diameter_mean},
            {"diameter_cv", m.holes.diameter_cv},
            {"spacing_mean_mm", m.holes.spacing_mean},
            {"spacing_cv", m.holes.spacing_cv},
            {"cell_area_cv", m.holes.cell_area_cv},
            {"porosity", m.holes.porosity}}},
          {"reduction", m.reduction ? json{{"triangles_before", m.reduction->triangles_before},
                                           {"triangles_after", m.reduction->triangles_after},
                                           {"max_distance_mm", m.reduction->max_distance},
                                           {"sampled_distance_mm", m.reduction->sampled_distance},
                                           {"sampled_points", m.reduction->sampled_points},
                                           {"reached_target", m.reduction->reached_target}}
                                    : json(nullptr)},
          {"wall",
           {{"requested_mm", r.solid.wall_mm},
            {"measured_median_mm", m.wall.median},
            {"measured_min_mm", m.wall.min},
            {"measured_max_mm", m.wall.max},
            {"measured_p5_mm", m.wall.low},
            {"measured_p95_mm", m.wall.high},
            {"probes", m.wall.probes},
            {"merged_probes", m.wall.merged}}}};
}

}  // namespace

json to_json(std::span<const Hole> holes) {
  json table = json::array();
  for (const Hole& h : holes)
    table.push_back({{"centre", h.centre},
                     {"normal", h.normal},
                     {"diameter", h.diameter},
                     {"circularity", h.circularity},
                     {"axis_ratio", h.axis_ratio},
                     {"nearest", h.nearest},
                     {"asked_diameter", h.asked_diameter}});
  return table;
}

namespace {

// The holes asked, planned and graded (empty for the paper's parameters).
json holes_json(const Report& r) {
  json holes = json::object();
  if (r.plan)
    holes = {{"requested",
              {{"diameter_mm", r.requested.diameter},
               {"spacing_mm", r.requested.spacing},
               {"porosity", r.requested.porosity}}},
             {"planned",
              {{"diameter_mm", r.plan->diameter},
               {"spacing_mm", r.plan->spacing},
               {"porosity", r.plan->porosity},
               {"pore_level", r.plan->pore_level},
               {"voxel_size_mm", r.plan->voxel_size}}}};
  if (r.grading)
    holes["grading"] = {{"min_diameter_mm", r.grading->min_diameter},
                        {"max_diameter_mm", r.grading->max_diameter},
                        {"clamped_fraction", r.grading->clamped_fraction},
                        {"printable_min_mm", r.grading->printable_min},
                        {"printable_max_mm", r.grading->printable_max}};
  return holes;
}

json solver_json(const Report& r) {
  json energy_trace = json::array();
  for (const auto& [step, e] : r.solver.energy_trace) energy_trace.push_back({step, e});
  json coarse_start = nullptr;  // no coarse start
  if (const auto& c = r.solver.coarse_start)
    coarse_start = {{"grid", c->grid},
                    {"h_mm", c->h_mm},
                    {"band_voxels", c->band_voxels},
                    {"steps", c->steps},
                    {"final_ec", c->final_ec},
                    {"reached_tolerance", c->reached_tolerance},
                    {"inner_iterations", c->inner_iterations},
                    {"repeated_steps", c->repeated_steps},
                    {"spots", c->spots},
                    {"seconds", c->seconds}};
  return {{"name", r.solver.name},
          {"inner_iteration", r.solver.inner_iteration},
          {"steps", r.solver.steps},
          {"final_ec", r.solver.final_ec},
          {"reached_tolerance", r.solver.reached_tolerance},
          {"stop_rule", r.solver.stop_rule},
          {"layout", r.solver.layout},
          {"layout_holes", r.solver.layout_holes},
          {"inner_converged", r.solver.inner_converged},
          {"inner_iterations", r.solver.inner_iterations},
          {"repeated_steps", r.solver.repeated_steps},
          {"coarse_start", coarse_start},
          {"energy",
           {{"first", number_or_null(r.solver.energy_first)},
            {"last", number_or_null(r.solver.energy_last)},
            {"trace", energy_trace}}}};
}

json input_json(const Report& r) {
  return {{"kind", r.input.kind},
          {"name", r.input.name},
          {"vertices", r.input.vertices},
          {"triangles", r.input.triangles},
          {"boundary_edges", r.input.boundary_edges},
          {"dropped_degenerate", r.input.dropped_degenerate},
          {"dropped_duplicate", r.input.dropped_duplicate},
          {"euler_characteristic", r.input.euler_characteristic},
          {"scale_to_grid", r.input.scale_to_grid},
          {"point_route", r.input.point_route},  // points only: direct | paper
          {"densified_points", r.input.densified_points},
          {"segmentation_iterations", r.input.segmentation_iterations},
          {"thin_feature_vertices", r.input.thin_vertices},
          {"crease_edges", r.input.crease_edges}};
}

}  // namespace

json to_json(const Report& r, std::span<const Output> outputs) {
  json meshes = json::array();
  for (std::size_t i = 0; i < r.outputs.size(); ++i) {
    meshes.push_back(level_json(r.outputs[i], r));
    if (i < outputs.size()) meshes.back()["hole_table"] = to_json(outputs[i].holes);
  }
  json mesh = meshes.empty() ? json::object() : meshes.front();
  mesh["outputs"] = meshes;
  mesh["unperforated_euler_characteristic"] = r.unperforated_euler_characteristic;
  const double mm_per_grid = r.input.mm_per_unit / r.input.scale_to_grid;
  return {
      {"version", r.version},
      {"command_line", r.command_line},
      {"settings", options_json(r.settings)},
      {"input", input_json(r)},
      {"units", {{"input", r.input.units}, {"input_mm_per_unit", r.input.mm_per_unit}, {"output", "mm"}}},
      {"grid",
       {{"dims", r.grid_dims}, {"h", r.h}, {"h_input_units", r.h / r.input.scale_to_grid}, {"h_mm", r.h_mm}}},
      {"solid",
       {{"mode", r.solid.mode},
        {"wall_mm", r.solid.wall_mm},
        {"wall_source", r.solid.wall_source},
        {"offset", r.solid.offset},
        {"spacing_mm", r.solid.spacing_mm},
        {"samples", r.solid.samples},
        {"incomplete_stencils", r.solid.incomplete_stencils},
        {"seconds_sample", r.solid.seconds_sample}}},
      {"band",
       {{"voxels", r.band.voxels},
        {"ghosts", r.band.ghosts},
        {"paper_ghosts", r.band.paper_ghosts},
        {"closure_added", r.band.closure_added},
        {"bytes", r.band.bytes}}},
      {"model",
       {{"alpha", r.model.alpha},
        {"epsilon", r.model.epsilon},
        {"phi_bar", r.model.phi_bar},
        {"dt", r.model.dt},
        {"alpha_per_mm2", r.model.alpha / (mm_per_grid * mm_per_grid)},
        {"epsilon_mm", r.model.epsilon * mm_per_grid},
        {"h_mm", r.h_mm}}},
      {"holes", holes_json(r)},
      {"solver", solver_json(r)},
      {"pattern",
       {{"spots", r.pattern.spots},
        {"closed_small_holes", r.pattern.closed_small_holes},
        {"closed_oblong_holes", r.pattern.closed_oblong_holes},
        {"rounded_oblong_holes", r.pattern.rounded_oblong_holes},
        {"closed_rim_holes", r.pattern.closed_rim_holes},
        {"size_cv", r.pattern.size_cv},
        {"mean_size_voxels", r.pattern.mean_size_voxels},
        {"area_fraction", r.pattern.area_fraction},
        {"spacing_mean_voxels", r.pattern.spacing_mean_voxels},
        {"spacing_cv", r.pattern.spacing_cv}}},
      {"mesh", mesh},
      {"solid_zones_mm2",
       {{"surface", r.solid_zones.surface},
        {"thin_parts", r.solid_zones.thin},
        {"creases", r.solid_zones.creases},
        {"rims", r.solid_zones.rims},
        {"keep_outs", r.solid_zones.keep_outs},
        {"solid", r.solid_zones.solid}}},
      {"warnings", r.warnings},
      {"memory",
       {{"band_bytes", r.memory.band_bytes},
        {"solver_bytes", r.memory.solver_bytes},
        {"peak_rss_after_band", r.memory.peak_rss_after_band},
        {"peak_rss_after_solve", r.memory.peak_rss_after_solve},
        {"peak_rss_total", r.memory.peak_rss_total},
        {"peak_rss_after_solve_per_band_voxel",
         r.band.voxels
             ? static_cast<double>(r.memory.peak_rss_after_solve) / static_cast<double>(r.band.voxels)
             : 0.0}}},
      {"seconds",
       {{"input", r.seconds.input},
        {"band", r.seconds.band},
        {"solve", r.seconds.solve},
        {"mesh", r.seconds.mesh},
        {"total", r.seconds.total}}},
      {"threads", r.threads},
      {"preview", r.preview},
  };
}

}  // namespace poreshell
