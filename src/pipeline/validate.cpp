#include "pipeline/validate.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "band/band.hpp"
#include "core/error.hpp"
#include "io/option_range.hpp"
#include "poreshell/option_table.hpp"

namespace poreshell {
namespace {

bool finite(double x) {
  return std::isfinite(x);
}

void require(bool ok, const char* option, const std::string& message) {
  if (!ok) throw OptionError(option, message);
}

// A voxel size up to this factor above the hole map's keeps the pattern's interface resolved
// (eps >= 0.77 h); coarser grids change the spacing.
constexpr double kCoarsestVoxelPerPlanned = 1.25;

// Rounded for people (issue 48: messages said 3.000000 mm).
std::string mm(double x) {
  return fmt::format("{:.3g}", x);
}

}  // namespace

void validate(const Options& c) {
  // Each option alone: its range is its row's in the option table.
  for (const OptionInfo& info : option_table()) check_range(info, c);
  // The rest: what a range cannot say, and options against each other.
  require(c.mode == Mode::shell || (c.wall == 0.0 && c.offset == WallOffset::centered), "wall",
          "`wall` and `offset` shape the shell: use them with `mode` shell");
  for (const KeepOutSphere& k : c.keep_out)
    require(k.radius > 0.0 && finite(k.centre[0] + k.centre[1] + k.centre[2] + k.radius), "keep_out",
            "`keep_out` takes X,Y,Z,R in mm with a radius R > 0");
  for (const KeepOutBox& k : c.keep_out_boxes)
    require(k.max[0] > k.min[0] && k.max[1] > k.min[1] && k.max[2] > k.min[2] &&
                finite(k.min[0] + k.min[1] + k.min[2] + k.max[0] + k.max[1] + k.max[2]),
            "keep_out_boxes",
            "`keep_out_boxes` takes X0,Y0,Z0,X1,Y1,Z1 in mm with X0 < X1, Y0 < Y1 and Z0 < Z1");
  const bool zones =
      c.rim > 0.0 || !c.keep_out.empty() || !c.keep_out_boxes.empty() || !c.keep_out_mask.empty();
  require(!zones || c.solver == SolverKind::fast, "solver",
          "`rim` and `keep_out` act through the fast solver: use `solver` fast");
  for (std::size_t i = 0; i < c.iso.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      require(c.iso[j] != c.iso[i], "iso", "`iso` lists the same level twice");
  const bool holes = c.hole_diameter > 0.0 || c.spacing > 0.0 || c.porosity > 0.0;
  // One way of asking: the hole map sets the paper's model from holes in mm, so a given one would be
  // silently ignored (issue 48).
  const char* hole = c.hole_diameter > 0.0 ? "hole_diameter" : c.spacing > 0.0 ? "spacing" : "porosity";
  for (const auto& [name, given] : {std::pair{"alpha", !std::isnan(c.alpha)},
                                    {"epsilon_m", !std::isnan(c.epsilon_m)},
                                    {"dt_h", !std::isnan(c.dt_h)},
                                    {"phi_bar", !std::isnan(c.phi_bar)},
                                    {"iso", !c.iso.empty()}})
    require(!holes || !given, name,
            fmt::format("`{}` is one of the paper's parameters, which the hole map sets from `{}`: give "
                        "holes in mm or the paper's parameters, not both",
                        name, hole));
  require(!c.grade || holes, "grade",
          "`grade` sets hole diameters in mm: add `hole_diameter` MM (and `spacing` MM or `porosity` F)");
  require(c.layout != Layout::cvt || holes, "layout",
          "`layout` cvt places holes at the spacing asked in mm: add `hole_diameter` MM (and `spacing` MM "
          "or `porosity` F), or use `layout` paper");
  // Fewer than a tetrahedron's four is no closed mesh; 0 sits apart from the range (no count).
  require(c.max_triangles == 0 || c.max_triangles >= 4, "max_triangles",
          "`max_triangles` must be at least 4 (0: keep every triangle)");
  require(c.max_triangles == 0 || c.max_deviation > 0.0, "max_triangles",
          "`max_triangles` needs a `max_deviation` above 0 mm to reduce within: drop `max_deviation` 0 "
          "(default 0.02 mm) or `max_triangles`");
  require(!c.lean || c.max_deviation > 0.0, "lean",
          "`lean` reduces within `max_deviation`, which is 0 (the full isosurface): drop `max_deviation` 0 "
          "(default 0.02 mm) or `lean`");
}

double choose_voxel_size(double asked, const PatternPlan& plan) {
  if (asked <= 0.0) return plan.voxel_size;
  require(asked <= kCoarsestVoxelPerPlanned * plan.voxel_size, "voxel_size",
          "`voxel_size` " + mm(asked) + " mm is too coarse for holes at " + mm(plan.spacing) +
              " mm spacing: use at most " +
              fmt::format("{:g}", rounded_down(kCoarsestVoxelPerPlanned * plan.voxel_size)) +
              " mm, or leave `voxel_size` out (" + mm(plan.voxel_size) + " mm)");
  return asked;
}

double rounded_down(double x) {
  if (!(x > 0.0) || !std::isfinite(x)) return x;
  const double unit = std::pow(10.0, std::floor(std::log10(x)) - 2.0);  // three significant digits
  double r = std::floor(x / unit) * unit;
  // Printing with {:g} must give a number no larger than x, whatever the last bit of r.
  while (std::stod(fmt::format("{:g}", r)) > x) r -= unit;
  return r;
}

double reduction_bound(const Options& c, double wall_mm) {
  return c.max_deviation == kDefaultMaxDeviation ? std::min(c.max_deviation, 0.25 * wall_mm)
                                                 : c.max_deviation;
}

void check_reduction(const Options& c, double wall_mm) {
  // The advice is rounded down so that following it is accepted (issue 47, item 7).
  require(
      reduction_bound(c, wall_mm) <= 0.25 * wall_mm, "max_deviation",
      fmt::format("`max_deviation` {:g} mm is more than a quarter of the {:g} mm wall: the reduced wall's "
                  "two sides could meet; use at most {:g} mm",
                  c.max_deviation, wall_mm, rounded_down(0.25 * wall_mm)));
}

}  // namespace poreshell
