#include "pattern/grading.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "io/text_scan.hpp"
#include "pattern/hole_map.hpp"

namespace poreshell {
namespace {

constexpr const char* kForms =
    "use axis:x|y|z:D1:D2, line:X,Y,Z:D1:X,Y,Z:D2, radial:X,Y,Z:R:D0 or field:NAME[:D0:D1] (lengths in mm)";

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

double number(const std::string& text, const std::string& whole) {
  std::size_t used = 0;
  double value = std::numeric_limits<double>::quiet_NaN();
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value))
    throw OptionError("grade",
                      "`grade` '" + whole + "': '" + text::quote(text) + "' is not a number; " + kForms);
  return value;
}

double diameter(const std::string& text, const std::string& whole) {
  const double d = number(text, whole);
  if (!(d > 0.0)) throw OptionError("grade", "`grade` '" + whole + "': hole diameters must be positive");
  return d;
}

Point point(const std::string& text, const std::string& whole) {
  const std::vector<std::string> xyz = split(text, ',');
  if (xyz.size() != 3) throw OptionError("grade", "`grade` '" + whole + "': a point is X,Y,Z; " + kForms);
  return {number(xyz[0], whole), number(xyz[1], whole), number(xyz[2], whole)};
}

}  // namespace

Grade parse_grade(const std::string& raw) {
  // Messages quote the spec: control characters (a newline) would break the one-line error.
  const std::string text = text::quote(raw, 120);
  const std::vector<std::string> p = split(raw, ':');
  Grade g;
  const std::string kind = p.empty() ? "" : p[0];
  if (kind == "axis" && p.size() == 4) {
    const std::string axes = "xyz";
    if (p[1].size() != 1 || axes.find(p[1][0]) == std::string::npos)
      throw OptionError("grade", "`grade` '" + text + "': the axis is x, y or z");
    g.kind = Grade::Kind::axis;
    g.axis = static_cast<int>(axes.find(p[1][0]));
    g.from_diameter = diameter(p[2], text);
    g.to_diameter = diameter(p[3], text);
  } else if (kind == "line" && p.size() == 5) {
    g.kind = Grade::Kind::line;
    g.from = point(p[1], text);
    g.from_diameter = diameter(p[2], text);
    g.to = point(p[3], text);
    g.to_diameter = diameter(p[4], text);
    // squaredNorm, not norm: the line's parameter divides by it, which must be neither 0 nor inf.
    const double length2 = (vec(g.to) - vec(g.from)).squaredNorm();
    if (!(length2 > 0.0) || !std::isfinite(length2))
      throw OptionError(
          "grade", "`grade` '" + text +
                       "': the two points coincide or are too far apart; give two distinct points in mm");
  } else if (kind == "radial" && p.size() == 4) {
    g.kind = Grade::Kind::radial;
    g.from = point(p[1], text);
    g.radius = number(p[2], text);
    if (!(g.radius > 0.0)) throw OptionError("grade", "`grade` '" + text + "': the radius must be positive");
    g.from_diameter = diameter(p[3], text);
  } else if (kind == "field" && (p.size() == 2 || p.size() == 4) && !p[1].empty()) {
    g.kind = Grade::Kind::field;
    g.field = p[1];
    if (p.size() == 4) {
      g.mapped = true;
      g.from_diameter = diameter(p[2], text);
      g.to_diameter = diameter(p[3], text);
    }
  } else {
    throw OptionError("grade", "`grade` '" + text + "' is not understood: " + kForms);
  }
  return g;
}

std::function<double(const Vec3&)> graded_diameter(const Grade& grade, const Box& bounds, double base,
                                                   std::function<double(const Vec3&)> field) {
  const auto blend = [](double a, double b, double t) { return a + std::clamp(t, 0.0, 1.0) * (b - a); };
  // The lambdas capture these, not the Grade with its name string.
  const Vec3 from = vec(grade.from), to = vec(grade.to);
  const double d0 = grade.from_diameter, d1 = grade.to_diameter, radius = grade.radius;
  const int axis = grade.axis;
  switch (grade.kind) {
    case Grade::Kind::axis: {
      const double lo = bounds.min[axis], extent = bounds.max[axis] - lo;
      return [=](const Vec3& x) { return blend(d0, d1, extent > 0.0 ? (x[axis] - lo) / extent : 0.0); };
    }
    case Grade::Kind::line: {
      const Vec3 u = to - from;
      return [=](const Vec3& x) { return blend(d0, d1, (x - from).dot(u) / u.squaredNorm()); };
    }
    case Grade::Kind::radial:
      return [=](const Vec3& x) {
        const double t = std::clamp((x - from).norm() / radius, 0.0, 1.0);
        return blend(d0, base, t * t * (3.0 - 2.0 * t));  // smoothstep: no kink at R
      };
    case Grade::Kind::field:
      if (!field)
        throw OptionError("grade", "`grade` field:" + text::quote(grade.field) +
                                       " needs a PLY mesh with that vertex property");
      if (!grade.mapped) return field;
      return [=](const Vec3& x) { return blend(d0, d1, field(x)); };
  }
  return [base](const Vec3&) { return base; };
}

LevelForRatio disc_levels(const PatternPlan& plan) {
  // The contour at r = d / 2 of tanh((R - r) / (sqrt 2 eps)), R putting the plan's level at D / 2.
  const double at_plan = std::atanh(plan.level), width = 2.0 * std::sqrt(2.0) * plan.epsilon;
  return [=](double ratio) { return std::tanh(at_plan + (plan.diameter - ratio * plan.spacing) / width); };
}

GradingSummary apply_grading(std::span<double> phi, std::span<const Vec3> positions_mm, double spacing,
                             double level, const std::function<double(const Vec3&)>& diameter_at,
                             const LevelForRatio& level_for_ratio) {
  GradingSummary s;
  s.clamped_min = min_diameter_ratio() * spacing;
  s.clamped_max = max_diameter_ratio() * spacing;
  s.min_diameter = std::numeric_limits<double>::infinity();
  s.max_diameter = -s.min_diameter;
  std::size_t clamped = 0;
  for (std::size_t v = 0; v < phi.size(); ++v) {
    const double d = diameter_at(positions_mm[v]);
    if (!std::isfinite(d))
      throw InputError("the grading gives no finite hole diameter near (" +
                       std::to_string(positions_mm[v].x()) + ", " + std::to_string(positions_mm[v].y()) +
                       ", " + std::to_string(positions_mm[v].z()) + ") mm: check the field's values");
    s.min_diameter = std::min(s.min_diameter, d);
    s.max_diameter = std::max(s.max_diameter, d);
    const double wanted = d / spacing;
    const double ratio = std::clamp(wanted, min_diameter_ratio(), max_diameter_ratio());
    if (ratio != wanted) ++clamped;
    phi[v] += level - level_for_ratio(ratio);
  }
  s.clamped_fraction = phi.empty() ? 0.0 : static_cast<double>(clamped) / static_cast<double>(phi.size());
  return s;
}

GradingSummary grade_holes(const Grade& grade, const std::function<double(const Vec3&)>& field,
                           const PlacedSurface& placed, const NarrowBand& band, const PatternPlan& plan,
                           std::vector<double>& phi, const LevelForRatio& level_for_ratio) {
  Box bounds{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
  std::vector<Vec3> positions(band.size());
  for (std::size_t v = 0; v < band.size(); ++v) {
    positions[v] = placed.to_mm(band.grid().position(band.voxels()[v]));
    bounds.min = bounds.min.cwiseMin(positions[v]);
    bounds.max = bounds.max.cwiseMax(positions[v]);
  }
  const auto diameter_at = graded_diameter(grade, bounds, plan.diameter, field);
  GradingSummary s = apply_grading(phi, positions, plan.spacing, plan.level, diameter_at, level_for_ratio);
  s.asked_diameter = [diameter_at, lo = s.clamped_min, hi = s.clamped_max](const Vec3& x) {
    return std::clamp(diameter_at(x), lo, hi);
  };
  return s;
}

}  // namespace poreshell
