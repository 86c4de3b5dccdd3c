#include "pipeline/stage_options.hpp"

namespace poreshell {

Layout resolve_layout(const Options& c, bool holes_in_mm) {
  if (c.layout != Layout::automatic) return c.layout;
  return holes_in_mm ? Layout::cvt : Layout::paper;
}

StopRule resolve_stop_rule(const Options& c, Layout layout) {
  if (c.stop != StopRule::automatic) return c.stop;
  // From the paper's noise the holes rule stops while the layout still glides (up to 0.24 spacing on
  // the bunny, docs/solver.md "Stop rules"): there it is only the preview's. From the even layout's
  // discs e_c falls under the tolerance while two discs may still be merging (the bunny's base: a
  // figure-eight hole at step 30); only the holes rule waits for that.
  return c.preview || layout == Layout::cvt ? StopRule::holes : StopRule::paper;
}

PlacementOptions placement_options(const Options& o) {
  return {o.resolution, o.voxel_size, o.scale, o.point_route, o.hole_diameter, o.spacing, holes_in_mm(o)};
}

ZoneOptions zone_options(const Options& o) {
  ZoneOptions zones{o.rim, {}, {}, o.thin_feature_ratio, o.crease_angle};
  for (const KeepOutSphere& k : o.keep_out) zones.keep_out.push_back({vec(k.centre), k.radius});
  for (const KeepOutBox& k : o.keep_out_boxes)
    zones.keep_out_boxes.push_back(SolidBox::spanned(vec(k.min), vec(k.max)));
  return zones;
}

SolveOptions solve_options(const Options& o, bool planned) {
  SolveOptions s;
  s.alpha = o.alpha;
  s.epsilon_m = o.epsilon_m;
  s.dt_h = o.dt_h;
  s.phi_bar = o.phi_bar;
  s.initial_amplitude = o.initial_amplitude;
  s.seed = o.seed;
  s.level = o.iso.empty() ? 0.0 : o.iso.front();
  s.preview = o.preview;
  s.layout = resolve_layout(o, planned);
  s.stop = resolve_stop_rule(o, s.layout);
  s.tolerance = o.tolerance;
  s.max_steps = o.max_steps;
  s.energy_every = o.energy_every;
  s.solver = o.solver;
  s.fast_tolerance = o.fast_tolerance;
  s.min_stabilisation = o.min_stabilisation;
  s.coarse_start = o.coarse_start;
  s.inner = o.inner;
  s.inner_tolerance = o.inner_tolerance;
  return s;
}

}  // namespace poreshell
