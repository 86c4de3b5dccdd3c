#pragma once
// From what a printer asks for (hole diameter, centre spacing or porosity, in millimetres) to the
// model's parameters (alpha, epsilon, phi_bar), the grid spacing h, the time step and the pore level.
//
// Physics (docs/printing.md): the nonlocal Cahn-Hilliard equation forms spots when the uniform state
// is unstable, 4 kappa < (1 - 3 phi_bar^2)^2 with kappa = alpha eps^2, and stripes instead of spots
// for |phi_bar| below about 0.29. The equilibrium spacing scales like (eps / alpha)^(1/3); at a fixed
// kappa that is a fixed multiple of eps. So the map fixes kappa and phi_bar (spots, away from both
// limits), sets eps from the spacing, h from eps (the interface resolved by about 4 cells) and the
// time step from eps^2 (the pattern's own time scale, so every length scale runs the same course),
// and picks the pore level {phi > level} that gives the hole diameter. The constants are measured
// (bench/calibrate_holes) on a sphere and on a flat sheet.

#include <span>
#include <string>

namespace poreshell {

struct HoleRequest {
  double diameter = 0.0;  // mm; 0: not given
  double spacing = 0.0;   // mm, centre to nearest centre; 0: not given
  double porosity = 0.0;  // open share of the surface; 0: not given
  bool empty() const { return diameter <= 0.0 && spacing <= 0.0 && porosity <= 0.0; }
};

// One row of the calibration: at pore level `level`, holes of diameter ratio * spacing and the open
// share `porosity` of the surface.
struct CalibrationRow {
  double level, diameter_ratio, porosity;
};

struct HoleCalibration {
  double kappa;                          // alpha eps^2
  double phi_bar;                        // mean concentration
  double epsilon_per_h;                  // eps / h: the interface over about 4 cells (the paper's eps_4)
  double spacing_per_epsilon;            // measured nearest-neighbour spacing / eps
  double dt_per_epsilon_squared;         // the paper's dt = 100 h at N = 131, over its eps_4^2
  std::span<const CalibrationRow> rows;  // by increasing level: decreasing diameter ratio
};

// The measured calibration (docs/printing.md).
const HoleCalibration& hole_calibration();

// The model for a request, in millimetres. Throws InputError for an impossible request, naming the
// nearest feasible one.
struct PatternPlan {
  double diameter = 0.0, spacing = 0.0, porosity = 0.0;  // as planned (the request completed), mm
  double epsilon = 0.0;                                  // mm
  double alpha = 0.0;                                    // 1 / mm^2
  double phi_bar = 0.0;
  double level = 0.0;       // holes are {phi > level}
  double voxel_size = 0.0;  // mm
};
PatternPlan plan_pattern(const HoleRequest& request);

// The calibration curve and its inverse, linear between rows; clamped to the table's ends.
double diameter_ratio_at_level(double level);
double level_for_diameter_ratio(double ratio);
double level_for_porosity(double porosity);

// The widest and narrowest holes, relative to the spacing, that the map offers: wider ones leave
// bridges too thin to print or merge into slots; narrower ones close up.
double max_diameter_ratio();
double min_diameter_ratio();

}  // namespace poreshell
