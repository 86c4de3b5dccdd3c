// The hole map (issue 4, item 3) and grading (item 4) as functions: the calibration inverts, the plan
// follows the model's physics and scales with the spacing, impossible requests are refused with the
// nearest feasible one, grading specs parse and clamp to printable holes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "pattern/grading.hpp"
#include "pattern/hole_map.hpp"
#include "test_support.hpp"

using namespace poreshell;

namespace {

std::string refusal(const HoleRequest& request) {
  return input_error([&] { plan_pattern(request); });
}

}  // namespace

TEST(HoleMap, CalibrationIsMonotoneAndInvertible) {
  double previous_ratio = 2.0;
  for (const CalibrationRow& row : hole_calibration().rows) {
    EXPECT_LT(row.diameter_ratio, previous_ratio);  // a higher pore level, smaller holes
    previous_ratio = row.diameter_ratio;
    EXPECT_NEAR(level_for_diameter_ratio(diameter_ratio_at_level(row.level)), row.level, 1e-12);
    EXPECT_NEAR(level_for_porosity(row.porosity), row.level, 1e-12);
  }
  for (double ratio = min_diameter_ratio(); ratio <= max_diameter_ratio(); ratio += 0.01)
    EXPECT_NEAR(diameter_ratio_at_level(level_for_diameter_ratio(ratio)), ratio, 1e-12);
}

TEST(HoleMap, PlanFollowsThePhysicsAndScalesWithTheSpacing) {
  const HoleCalibration& cal = hole_calibration();
  // Spots, not stripes or a uniform state: 4 kappa < (1 - 3 phi_bar^2)^2 and |phi_bar| above 0.29.
  EXPECT_LT(4 * cal.kappa, std::pow(1 - 3 * cal.phi_bar * cal.phi_bar, 2));
  EXPECT_GT(std::abs(cal.phi_bar), 0.29);
  const PatternPlan p = plan_pattern({6.0, 10.0, 0.0});
  EXPECT_DOUBLE_EQ(p.diameter, 6.0);
  EXPECT_DOUBLE_EQ(p.spacing, 10.0);
  EXPECT_NEAR(p.alpha * p.epsilon * p.epsilon, cal.kappa, 1e-12);
  EXPECT_NEAR(p.spacing / p.epsilon, cal.spacing_per_epsilon, 1e-12);
  EXPECT_NEAR(p.epsilon / p.voxel_size, cal.epsilon_per_h, 1e-12);
  EXPECT_NEAR(diameter_ratio_at_level(p.level), 0.6, 1e-12);
  // Twice the size: every length doubles, the level stays.
  const PatternPlan q = plan_pattern({12.0, 20.0, 0.0});
  EXPECT_NEAR(q.epsilon, 2 * p.epsilon, 1e-12);
  EXPECT_NEAR(q.voxel_size, 2 * p.voxel_size, 1e-12);
  EXPECT_NEAR(q.alpha, p.alpha / 4, 1e-12);
  EXPECT_DOUBLE_EQ(q.level, p.level);
  // Bigger holes at the same spacing need a lower pore level.
  EXPECT_LT(plan_pattern({7.0, 10.0, 0.0}).level, p.level);
}

TEST(HoleMap, CompletesPartialRequests) {
  const PatternPlan d = plan_pattern({6.0, 0.0, 0.0});
  EXPECT_NEAR(d.spacing, 10.0, 1e-9);  // the default ratio 0.6
  const PatternPlan a = plan_pattern({0.0, 10.0, 0.0});
  EXPECT_NEAR(a.diameter, 6.0, 1e-9);
  const PatternPlan dp = plan_pattern({6.0, 0.0, 0.3});
  EXPECT_NEAR(dp.porosity, 0.3, 1e-9);
  EXPECT_NEAR(dp.diameter, 6.0, 1e-9);
  const PatternPlan ap = plan_pattern({0.0, 10.0, 0.3});
  EXPECT_NEAR(ap.porosity, 0.3, 1e-9);
  EXPECT_NEAR(ap.diameter / ap.spacing, dp.diameter / dp.spacing, 1e-9);
  EXPECT_LT(plan_pattern({0.0, 10.0, 0.4}).level, ap.level);  // more open: larger holes
}

TEST(HoleMap, RefusesImpossibleRequestsNamingTheNearestFeasible) {
  const std::string wide = refusal({9.0, 10.0, 0.0});
  EXPECT_NE(wide.find("bridges too thin"), std::string::npos) << wide;
  EXPECT_NE(wide.find("`hole_diameter` 8 `spacing` 10"), std::string::npos) << wide;
  EXPECT_NE(wide.find("`hole_diameter` 9 `spacing` 11.2"), std::string::npos) << wide;
  const std::string narrow = refusal({2.0, 10.0, 0.0});
  EXPECT_NE(narrow.find("too small"), std::string::npos) << narrow;
  EXPECT_NE(narrow.find("`hole_diameter` 3.5 `spacing` 10"), std::string::npos) << narrow;
  EXPECT_NE(refusal({0.0, 10.0, 0.9}).find("porosity between"), std::string::npos);
  EXPECT_NE(refusal({6.0, 10.0, 0.3}).find("give two"), std::string::npos);
  EXPECT_NE(refusal({0.0, 0.0, 0.3}).find("`hole_diameter` MM or `spacing` MM"), std::string::npos);
  EXPECT_NE(refusal({-1.0, 10.0, 0.0}).find("positive"), std::string::npos);
  EXPECT_EQ(refusal({6.0, 10.0, 0.0}), "");
}

TEST(Grading, ParsesEveryFormAndRefusesTheRest) {
  const Grade axis = parse_grade("axis:z:4:8");
  EXPECT_EQ(axis.kind, Grade::Kind::axis);
  EXPECT_EQ(axis.axis, 2);
  EXPECT_DOUBLE_EQ(axis.to_diameter, 8.0);
  const Grade line = parse_grade("line:0,0,0:4:10,0,0:8");
  EXPECT_EQ(line.kind, Grade::Kind::line);
  EXPECT_DOUBLE_EQ(line.to[0], 10.0);
  const Grade radial = parse_grade("radial:1,2,3:20:7");
  EXPECT_EQ(radial.kind, Grade::Kind::radial);
  EXPECT_DOUBLE_EQ(radial.radius, 20.0);
  const Grade field = parse_grade("field:quality:4:8");
  EXPECT_TRUE(field.mapped);
  EXPECT_EQ(field.field, "quality");
  EXPECT_FALSE(parse_grade("field:hole_mm").mapped);
  for (const char* bad :
       {"", "axis:w:4:8", "axis:z:4", "axis:z:-4:8", "line:0,0:4:1,0,0:8", "line:0,0,0:4:0,0,0:8",
        "radial:0,0,0:0:5", "radial:0,0,0:x:5", "field:", "spiral:1"})
    EXPECT_THROW(parse_grade(bad), OptionError) << bad;
}

TEST(Grading, DiametersFollowTheSpecAndAreClampedToPrintableHoles) {
  const Box bounds{Vec3(0, 0, 0), Vec3(10, 10, 100)};
  const auto axis = graded_diameter(parse_grade("axis:z:4:8"), bounds, 6.0);
  EXPECT_DOUBLE_EQ(axis(Vec3(5, 5, 0)), 4.0);
  EXPECT_DOUBLE_EQ(axis(Vec3(5, 5, 50)), 6.0);
  EXPECT_DOUBLE_EQ(axis(Vec3(5, 5, 100)), 8.0);
  const auto line = graded_diameter(parse_grade("line:0,0,0:4:10,0,0:8"), bounds, 6.0);
  EXPECT_DOUBLE_EQ(line(Vec3(-5, 3, 0)), 4.0);  // constant beyond the ends
  EXPECT_DOUBLE_EQ(line(Vec3(5, 3, 7)), 6.0);
  const auto radial = graded_diameter(parse_grade("radial:0,0,0:10:8"), bounds, 6.0);
  EXPECT_DOUBLE_EQ(radial(Vec3::Zero()), 8.0);
  EXPECT_DOUBLE_EQ(radial(Vec3(0, 10, 0)), 6.0);
  EXPECT_DOUBLE_EQ(radial(Vec3(0, 5, 0)), 7.0);
  EXPECT_THROW(graded_diameter(parse_grade("field:q"), bounds, 6.0), OptionError);  // no field given

  // At spacing 10 the printable range is [3.5, 8] mm: a 9 mm request is clamped, and a larger hole is a
  // lower local level, i.e. phi raised.
  std::vector<double> phi{0.0, 0.0, 0.0};
  const std::vector<Vec3> at{Vec3(0, 0, 0), Vec3(0, 0, 50), Vec3(0, 0, 100)};
  const auto wide = graded_diameter(parse_grade("axis:z:6:9"), bounds, 6.0);
  const GradingSummary s = apply_grading(phi, at, 10.0, level_for_diameter_ratio(0.6), wide);
  EXPECT_NEAR(phi[0], 0.0, 1e-12);
  EXPECT_GT(phi[1], 0.0);
  EXPECT_GT(phi[2], phi[1]);
  EXPECT_NEAR(phi[2], level_for_diameter_ratio(0.6) - level_for_diameter_ratio(max_diameter_ratio()), 1e-12);
  EXPECT_NEAR(s.clamped_fraction, 1.0 / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.max_diameter, 9.0);
  EXPECT_DOUBLE_EQ(s.clamped_max, 8.0);
}
