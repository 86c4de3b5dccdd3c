// The holes rule against the paper's (docs/solver.md "Stop rules"), and the preview's wall time.
//
//   bench_stop compare [--seeds 5] [--cases sphere,bunny,sleeve]
//     Per case and seed: one run to the paper's e_c < 1e-3 on the hole map's grid, the state kept every
//     `every` steps; each candidate setting of the holes rule is replayed on those states. Prints per
//     setting the step it stops at, the steps saved and its holes against the paper run's: count and
//     diameter mean (relative differences) and the largest distance from a hole to the nearest hole of
//     the other run, in mean spacings. Then a check that the pipeline's own holes-rule run stops at the
//     replay's step for the default setting.
//   bench_stop preview [--repeats 3] [--seeds 5]
//     Wall time of perforate() with `preview` (bunny: load included; seed 1) and, per seed, how its
//     holes match the full run's.
//
// Cases: sphere(50) 6 mm holes at 10 mm; the bunny (data/stanford-bunny.obj, m) 8 at 14; the sleeve
// (open cylinder, radius 35 mm, length 200 mm) 8 at 12.

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "core/run_monitor.hpp"
#include "input/placement.hpp"
#include "pattern/hole_map.hpp"
#include "pattern/pattern.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/solve_stage.hpp"
#include "poreshell/poreshell.hpp"
#include "solver/fast_solver.hpp"
#include "solver/hole_stop.hpp"
#include "solver/initial_condition.hpp"
#include "solver/time_stepping.hpp"

namespace {

using namespace poreshell;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// An open cylinder along z, about 1 mm triangles.
MeshInput sleeve(double radius, double length) {
  MeshInput in;
  in.name = "sleeve";
  const int around = static_cast<int>(std::ceil(2.0 * std::numbers::pi * radius));
  const int along = static_cast<int>(std::ceil(length));
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) {
      const double a = 2.0 * std::numbers::pi * i / around;
      in.mesh.vertices.push_back({radius * std::cos(a), radius * std::sin(a), length * j / along});
    }
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const int a = j * around + i, b = j * around + (i + 1) % around;
      in.mesh.triangles.push_back({a, b, b + around});
      in.mesh.triangles.push_back({a, b + around, a + around});
    }
  return in;
}

struct Case {
  std::string name;
  Input input;
  double diameter, spacing;
};

Case make_case(const std::string& name) {
  if (name == "sphere") return {name, sphere(50.0), 6.0, 10.0};
  if (name == "bunny") return {name, load_mesh("data/stanford-bunny.obj", Unit::m), 8.0, 14.0};
  if (name == "sleeve") return {name, sleeve(35.0, 200.0), 8.0, 12.0};
  throw std::runtime_error("unknown case " + name);
}

// Largest distance from a hole of `a` to the nearest of `b`, in b's mean spacings.
double worst_match(const HoleStats& a, const HoleStats& b) {
  std::vector<Vec3> pa, pb;
  for (const BandHole& h : a.holes) pa.push_back(h.centroid);
  for (const BandHole& h : b.holes) pb.push_back(h.centroid);
  return largest_nearest_distance(pa, pb) / b.spacing_mean;
}

struct Setting {
  int every, window;
  double shift, flipped;
};

void compare(const std::vector<std::string>& cases, int seeds, int every) {
  const std::vector<Setting> settings{
      {4, 16, 0.05, 1e-2}, {4, 16, 0.05, 7e-3}, {4, 16, 0.05, 1.4e-2}, {4, 24, 0.05, 1.5e-2}};
  const HoleStopOptions defaults;
  for (const std::string& name : cases) {
    Case c = make_case(name);
    Options options;
    options.hole_diameter = c.diameter;
    options.spacing = c.spacing;
    const PatternPlan plan = plan_pattern({c.diameter, c.spacing, 0.0});
    options.voxel_size = plan.voxel_size;
    options.iso = {plan.level};
    options.phi_bar = plan.phi_bar;
    const PlacedSurface placed = place_surface(c.input, placement_options(options));
    const Grid grid = Grid::fitted(placed.domain, placed.resolution);
    const NarrowBand band = build_band(*placed.surface, grid);
    ModelParameters model;
    double dt = 0.0;
    choose_model(solve_options(options, true), plan, placed.mm_per_grid(), grid.h(), model, dt);
    fmt::print("== {}: {} mm holes at {} mm, grid {}x{}x{}, voxel {:.3f} mm, band {} voxels, level {:.3f}\n",
               name, c.diameter, c.spacing, grid.dims()[0], grid.dims()[1], grid.dims()[2], plan.voxel_size,
               band.size(), plan.level);
    for (int seed = 1; seed <= seeds; ++seed) {
      std::vector<double> phi = random_initial_condition(band, model.phi_bar, options.initial_amplitude,
                                                         static_cast<std::uint64_t>(seed));
      FastSolver solver(band, model, dt, FastOptions{options.min_stabilisation, options.fast_tolerance, 60});
      std::vector<std::vector<float>> states{std::vector<float>(phi.begin(), phi.end())};
      std::vector<double> time_at{0.0};
      RunOptions run;
      run.tolerance = options.tolerance;
      run.max_steps = options.max_steps;
      run.min_spread = 1.0;
      double solve_seconds = 0.0;
      auto t = Clock::now();
      run.on_step = [&](const StepProgress& p) {
        solve_seconds += seconds_since(t);
        if (p.step % every == 0) {
          states.emplace_back(phi.begin(), phi.end());
          time_at.push_back(solve_seconds);
        }
        t = Clock::now();
      };
      const RunResult paper = run_to_steady_state(solver, phi, nullptr, run);
      const HoleStats final_holes = hole_statistics(band, phi, plan.level);
      // The cost of one check: the holes' labels and statistics plus the side mask.
      const auto tc = Clock::now();
      HoleStop probe(band, defaults);
      probe.settled(0, phi);
      const double check_seconds = seconds_since(tc);
      fmt::print(
          "  seed {}: paper rule {} steps, {:.2f} s solve ({:.1f} ms a step), {} holes, diameter {:.3f} mm; "
          "one check {:.1f} ms\n",
          seed, paper.steps, solve_seconds, 1e3 * solve_seconds / paper.steps, final_holes.holes.size(),
          final_holes.diameter_mean * placed.mm_per_grid(), 1e3 * check_seconds);
      for (const Setting& s : settings) {
        if (s.every % every != 0) continue;
        HoleStopOptions o;
        o.level = plan.level;
        o.every = s.every;
        o.window = s.window;
        o.max_shift = s.shift;
        o.max_flipped = s.flipped;
        HoleStop stop(band, o);
        std::size_t at = states.size();
        std::vector<double> state;
        for (std::size_t k = 0; k < states.size(); ++k) {
          state.assign(states[k].begin(), states[k].end());
          if (stop.settled(static_cast<int>(k) * every, state)) {
            at = k;
            break;
          }
        }
        if (at == states.size()) {
          fmt::print("    every {} window {:2d} shift {:.2f} flipped {:.0e}: never settled\n", s.every,
                     s.window, s.shift, s.flipped);
          continue;
        }
        const HoleStats holes = hole_statistics(band, state, plan.level);
        const int steps = static_cast<int>(at) * every;
        const double n0 = static_cast<double>(final_holes.holes.size());
        fmt::print(
            "    every {} window {:2d} shift {:.2f} flipped {:.0e}: stops at {:4d} (saves {:4d} steps, "
            "{:3.0f}%), "
            "count {:+.2f}%, diameter {:+.2f}%, worst hole {:.3f} / {:.3f} spacing\n",
            s.every, s.window, s.shift, s.flipped, steps, paper.steps - steps,
            100.0 * (paper.steps - steps) / paper.steps,
            100.0 * (static_cast<double>(holes.holes.size()) - n0) / n0,
            100.0 * (holes.diameter_mean / final_holes.diameter_mean - 1.0), worst_match(holes, final_holes),
            worst_match(final_holes, holes));
      }
      if (seed == 1) {  // the pipeline's own holes-rule run (a preview: the same grid and solve)
        Options p = options;
        p.voxel_size = 0.0;
        p.iso = {0.0};
        p.phi_bar = PaperModel::phi_bar;
        p.seed = static_cast<std::uint64_t>(seed);
        p.preview = true;
        p.layout = Layout::paper;  // the even layout's preview runs no equation
        const PipelineResult r = run_pipeline(c.input, p, unmonitored());
        fmt::print("    pipeline, holes rule (default): {} steps, {} holes, worst hole {:.3f} spacing\n",
                   r.solve.run.steps, r.meshes[0].holes.holes.size(),
                   largest_nearest_distance(
                       [&] {
                         std::vector<Vec3> v;
                         for (const BandHole& h : r.meshes[0].holes.holes)
                           v.push_back(placed.from_mm(h.centroid));
                         return v;
                       }(),
                       [&] {
                         std::vector<Vec3> v;
                         for (const BandHole& h : final_holes.holes) v.push_back(h.centroid);
                         return v;
                       }()) /
                       final_holes.spacing_mean);
      }
      std::fflush(stdout);
    }
  }
}

void preview(int repeats, int seeds) {
  for (const std::string& name : {std::string("bunny"), std::string("sleeve")}) {
    for (int seed = 1; seed <= seeds; ++seed) {
      // Timed on the first seed only; the others for the match.
      std::vector<double> walls;
      Result last;
      for (int r = 0; r < (seed == 1 ? repeats : 1); ++r) {
        const auto t = Clock::now();
        const Case c = make_case(name);
        Options o;
        o.hole_diameter = c.diameter;
        o.spacing = c.spacing;
        o.seed = static_cast<std::uint64_t>(seed);
        o.preview = true;
        last = perforate(c.input, o);
        walls.push_back(seconds_since(t));
      }
      std::sort(walls.begin(), walls.end());
      const Report& rep = last.report;
      // The full run with the same seed: the issue asks for the count within 3% and every preview hole
      // within 0.15 spacing of a full-run hole.
      const Case c = make_case(name);
      Options full;
      full.hole_diameter = c.diameter;
      full.spacing = c.spacing;
      full.seed = static_cast<std::uint64_t>(seed);
      const Result f = perforate(c.input, full);
      std::vector<Vec3> seen, made;
      for (const Hole& h : last.outputs[0].holes) seen.emplace_back(h.centre[0], h.centre[1], h.centre[2]);
      for (const Hole& h : f.outputs[0].holes) made.emplace_back(h.centre[0], h.centre[1], h.centre[2]);
      std::vector<double> offsets;
      for (const Vec3& x : seen) {
        double best = std::numeric_limits<double>::infinity();
        for (const Vec3& y : made) best = std::min(best, (x - y).norm());
        offsets.push_back(best / full.spacing);
      }
      std::sort(offsets.begin(), offsets.end());
      const auto within = std::count_if(offsets.begin(), offsets.end(), [](double d) { return d <= 0.15; });
      fmt::print(
          "{} seed {}: full run {} holes ({:+.1f}% from the preview's), {:.2f} s; preview holes within 0.15 "
          "spacing of one: {} of {} ({} discs closed as the run would), median offset {:.3f}, worst {:.3f} "
          "spacing\n",
          name, seed, made.size(),
          100.0 * (static_cast<double>(seen.size()) / static_cast<double>(made.size()) - 1.0),
          f.report.seconds.total, within, seen.size(), rep.pattern.closed_small_holes,
          offsets.empty() ? 0.0 : offsets[offsets.size() / 2], offsets.empty() ? 0.0 : offsets.back());
      if (seed == 1)
        fmt::print(
            "{} preview: wall min {:.3f} s, median {:.3f} s (input {:.3f}, band {:.3f}, solve {:.3f}, mesh "
            "{:.3f}); {} steps, {} holes, {} band voxels, {} surface triangles\n",
            name, walls.front(), walls[walls.size() / 2], rep.seconds.input, rep.seconds.band,
            rep.seconds.solve, rep.seconds.mesh, rep.solver.steps, last.outputs[0].holes.size(),
            rep.band.voxels, last.outputs[0].mesh.triangles.size());
      std::fflush(stdout);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"poreshell stop rules and preview"};
  std::string mode = "compare";
  int seeds = 5, repeats = 3, every = 4;
  std::vector<std::string> cases{"sphere", "bunny", "sleeve"};
  app.add_option("mode", mode)->check(CLI::IsMember({"compare", "preview"}));
  app.add_option("--seeds", seeds);
  app.add_option("--cases", cases)->delimiter(',');
  app.add_option("--repeats", repeats);
  app.add_option("--every", every);
  CLI11_PARSE(app, argc, argv);
  if (mode == "compare")
    compare(cases, seeds, every);
  else
    preview(repeats, seeds);
  return 0;
}
