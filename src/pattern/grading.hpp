#pragma once
// Hole-size grading (the paper's Figs. 13-14, generalised): a target hole diameter over the surface,
// realised as a local pore level, so holes grow or shrink where asked while the pattern the solver
// formed (hole positions and count) stays as it is. Diameters are in millimetres, like positions.
//
//   axis:x|y|z:D1:D2            D1 at the model's lowest extent along the axis to D2 at its highest
//   line:X,Y,Z:D1:X,Y,Z:D2      D1 at the first point to D2 at the second, constant beyond them
//   radial:X,Y,Z:R:D0           D0 at the centre, easing to the base diameter at distance R
//   field:NAME[:D0:D1]          a scalar per vertex of a PLY mesh: diameters in mm, or 0..1 mapped to
//                               D0..D1

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "core/types.hpp"
#include "input/placement.hpp"
#include "pattern/hole_map.hpp"
#include "poreshell/options.hpp"

namespace poreshell {

// The grading is the public Grade (include/poreshell/options.hpp), parsed by parse_grade, which throws
// OptionError naming the accepted forms.

// The target diameter at a point (mm), for a grading over a model with bounds `bounds` and a base
// diameter (the request's); `field` evaluates the PLY property at a point (field gradings only).
std::function<double(const Vec3&)> graded_diameter(const Grade& grade, const Box& bounds, double base,
                                                   std::function<double(const Vec3&)> field = {});

struct GradingSummary {
  double min_diameter = 0.0, max_diameter = 0.0;  // requested over the band, mm
  double clamped_fraction = 0.0;                // share of band voxels whose request left the printable range
  double clamped_min = 0.0, clamped_max = 0.0;  // the printable range at this spacing, mm
  // The diameter asked at a point (mm, the band's frame in mm), clamped as it was applied.
  std::function<double(const Vec3&)> asked_diameter;
};

// The pore level at which holes are `ratio` times the spacing across.
using LevelForRatio = std::function<double(double ratio)>;
// That level for the even layout's discs as placed, tanh((R - r) / (sqrt 2 eps)) with the plan's level
// at r = D / 2: what a preview that does not run the equation shows. The equation's pores follow the
// hole map's calibration instead, level_for_diameter_ratio.
LevelForRatio disc_levels(const PatternPlan& plan);

// Shifts phi by (level - level(x)) so that {phi > level} has, near each voxel, the holes asked for
// there; diameters outside [min, max] ratio times the spacing are clamped (no hole swallows its
// neighbours, none closes up).
GradingSummary apply_grading(std::span<double> phi, std::span<const Vec3> positions_mm, double spacing,
                             double level, const std::function<double(const Vec3&)>& diameter_at,
                             const LevelForRatio& level_for_ratio = level_for_diameter_ratio);

// Grades the pattern on the band: phi shifted per voxel so that {phi > plan.level} has the graded holes.
// `field` evaluates the named vertex field at a point in mm (field gradings only).
GradingSummary grade_holes(const Grade& grade, const std::function<double(const Vec3&)>& field,
                           const PlacedSurface& placed, const NarrowBand& band, const PatternPlan& plan,
                           std::vector<double>& phi,
                           const LevelForRatio& level_for_ratio = level_for_diameter_ratio);

}  // namespace poreshell
