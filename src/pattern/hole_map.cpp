#include "pattern/hole_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace poreshell {
namespace {

// Measured by bench/calibrate_holes (docs/printing.md): means over seeds 1-3 and over a sphere (radius
// 3.8 spacings) and a flat sheet, which differ by at most 0.012 in the ratio and 0.004 in porosity.
constexpr std::array<CalibrationRow, 15> kRows{{
    {-0.60, 0.845, 0.534},
    {-0.55, 0.796, 0.474},
    {-0.50, 0.759, 0.430},
    {-0.40, 0.702, 0.369},
    {-0.30, 0.658, 0.323},
    {-0.20, 0.618, 0.287},
    {-0.10, 0.585, 0.256},
    {0.00, 0.553, 0.228},
    {0.10, 0.520, 0.202},
    {0.20, 0.487, 0.178},
    {0.30, 0.452, 0.153},
    {0.40, 0.414, 0.128},
    {0.50, 0.370, 0.102},
    {0.55, 0.344, 0.089},
    {0.60, 0.314, 0.074},
}};

constexpr HoleCalibration kCalibration{
    0.076,    // kappa: the paper's sphere, 1400 eps_4^2 at N = 131
    -0.33,    // phi_bar: between stripes (|phi_bar| < 0.29) and no pattern (0.387 at this kappa)
    0.961,    // eps / h: the paper's eps_4 = 4 h / (2 sqrt 2 atanh 0.9)
    12.65,    // spacing / eps: sphere 12.59, sheet 12.72 (the same at eps = 1.6 h: 12.53)
    14085.0,  // dt / eps^2: the paper's dt = 100 h with h = 1/130, over eps_4^2
    kRows};

// Ratios of hole diameter to spacing the map offers (see max_diameter_ratio).
constexpr double kMaxRatio = 0.80, kMinRatio = 0.35;
// Default ratio when only one length is given: a third of the surface open, bridges of 0.4 spacing.
constexpr double kDefaultRatio = 0.6;

// y(x) by linear interpolation in the rows, with x and y chosen by the accessors; rows sorted by x
// (ascending or descending), clamped at the ends.
template <class X, class Y>
double interpolate(double x, X x_of, Y y_of) {
  const auto rows = kCalibration.rows;
  const bool ascending = x_of(rows.front()) <= x_of(rows.back());
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double x0 = x_of(rows[i - 1]), x1 = x_of(rows[i]);
    if (ascending ? x > x1 : x < x1) continue;
    const double t = std::clamp((x - x0) / (x1 - x0), 0.0, 1.0);
    return y_of(rows[i - 1]) + t * (y_of(rows[i]) - y_of(rows[i - 1]));
  }
  return y_of(rows.back());
}

std::string format_mm(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

}  // namespace

const HoleCalibration& hole_calibration() {
  return kCalibration;
}

double diameter_ratio_at_level(double level) {
  return interpolate(
      level, [](const CalibrationRow& r) { return r.level; },
      [](const CalibrationRow& r) { return r.diameter_ratio; });
}

double level_for_diameter_ratio(double ratio) {
  return interpolate(
      ratio, [](const CalibrationRow& r) { return r.diameter_ratio; },
      [](const CalibrationRow& r) { return r.level; });
}

double level_for_porosity(double porosity) {
  return interpolate(
      porosity, [](const CalibrationRow& r) { return r.porosity; },
      [](const CalibrationRow& r) { return r.level; });
}

double max_diameter_ratio() {
  return kMaxRatio;
}
double min_diameter_ratio() {
  return kMinRatio;
}

PatternPlan plan_pattern(const HoleRequest& request) {
  const double d = request.diameter, a = request.spacing, p = request.porosity;
  if (!(d >= 0.0 && a >= 0.0 && p >= 0.0) || !std::isfinite(d + a + p))
    throw OptionError("hole_diameter", "`hole_diameter`, `spacing` and `porosity` must be positive numbers");
  if (d > 0.0 && a > 0.0 && p > 0.0)
    throw OptionError(
        "porosity", "`hole_diameter`, `spacing` and `porosity` over-determine the pattern: give two of them");
  if (p > 0.0 && d <= 0.0 && a <= 0.0)
    throw OptionError(
        "porosity",
        "`porosity` sets how much is open, not how large the holes are: add `hole_diameter` MM or "
        "`spacing` MM");
  const auto porosity_at = [](double ratio) {
    return interpolate(
        level_for_diameter_ratio(ratio), [](const CalibrationRow& r) { return r.level; },
        [](const CalibrationRow& r) { return r.porosity; });
  };
  const double min_porosity = porosity_at(kMinRatio), max_porosity = porosity_at(kMaxRatio);
  if (p > 0.0 && (p < min_porosity || p > max_porosity))
    throw OptionError("porosity", "`porosity` " + format_mm(p) +
                                      " is outside what round, separate holes give: use a porosity between " +
                                      format_mm(min_porosity) + " and " + format_mm(max_porosity));

  PatternPlan plan;
  double ratio = kDefaultRatio;
  if (p > 0.0) ratio = diameter_ratio_at_level(level_for_porosity(p));
  plan.spacing = a > 0.0 ? a : (d > 0.0 ? d / ratio : 0.0);
  plan.diameter = d > 0.0 ? d : ratio * plan.spacing;
  ratio = plan.diameter / plan.spacing;
  if (ratio > kMaxRatio || ratio < kMinRatio) {
    const double nearest = std::clamp(ratio, kMinRatio, kMaxRatio);
    // Named as the hole diameter's fault, so that a form can mark that field (issue 50).
    throw OptionError(
        d > 0.0 ? "hole_diameter" : "spacing",
        "holes of " + format_mm(plan.diameter) + " mm at " + format_mm(plan.spacing) + " mm spacing " +
            (ratio > kMaxRatio ? "would leave bridges too thin to print or merge into slots"
                               : "are too small for their spacing to stay open") +
            " (the diameter must lie between " + format_mm(kMinRatio) + " and " + format_mm(kMaxRatio) +
            " times the spacing): the nearest feasible requests are `hole_diameter` " +
            format_mm(nearest * plan.spacing) + " `spacing` " + format_mm(plan.spacing) +
            ", or `hole_diameter` " + format_mm(plan.diameter) + " `spacing` " +
            format_mm(plan.diameter / nearest));
  }
  plan.level = level_for_diameter_ratio(ratio);
  plan.porosity = porosity_at(ratio);
  plan.phi_bar = kCalibration.phi_bar;
  plan.epsilon = plan.spacing / kCalibration.spacing_per_epsilon;
  plan.alpha = kCalibration.kappa / (plan.epsilon * plan.epsilon);
  plan.voxel_size = plan.epsilon / kCalibration.epsilon_per_h;
  return plan;
}

}  // namespace poreshell
