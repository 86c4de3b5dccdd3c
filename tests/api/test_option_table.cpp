// Issue 48: one option table that the report's `settings`, project files and the studio read. Every
// row reads and writes its own field, the JSON goes round unchanged, and a bad value is refused naming
// its option.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "poreshell/error.hpp"
#include "poreshell/option_table.hpp"

namespace poreshell {
namespace {

using nlohmann::json;

json settings(const Options& o) {
  return json::parse(options_to_json(o));
}

// A value of the row's type other than the default (in range), for the test below.
json other_value(const OptionInfo& info, const json& now) {
  switch (info.type) {
    case OptionType::number:
      return now.is_null() ? json(0.5) : json(now.get<double>() == 0.5 ? 0.25 : 0.5);
    case OptionType::integer:
      return now.get<std::int64_t>() == 17 ? 18 : 17;
    case OptionType::boolean:
      return !now.get<bool>();
    case OptionType::choice: {
      const std::string choices(info.choices);  // "a, b, c"
      const std::string first = choices.substr(0, choices.find(", "));
      const std::string rest = choices.substr(first.size() + 2);
      return now.get<std::string>() == first ? rest.substr(0, rest.find(", ")) : first;
    }
    case OptionType::text:
      return "thickness";
    case OptionType::numbers:
      return json::array({0.25, -0.25});
    case OptionType::spheres:
      return json::array({json::array({1.0, 2.0, 3.0, 4.0})});
    case OptionType::boxes:
      return json::array({json::array({0.0, 0.0, 0.0, 1.0, 2.0, 3.0})});
    case OptionType::grade:
      return {{"kind", "axis"}, {"axis", 1}, {"from_diameter", 4.0}, {"to_diameter", 8.0}};
  }
  return nullptr;
}

// Each row reads its own field and writes it back, and no other: set alone, only its key changes.
TEST(OptionTable, EachRowReadsAndWritesItsOwnField) {
  const json defaults = settings(Options{});
  ASSERT_EQ(defaults.size(), option_table().size()) << "a row for every key of the report's settings";
  std::set<std::string> names;
  for (const OptionInfo& info : option_table()) {
    EXPECT_TRUE(names.insert(std::string(info.name)).second) << info.name << " twice";
    EXPECT_EQ(find_option(info.name), &info);
    EXPECT_FALSE(info.help.empty()) << info.name;
    const std::string name(info.name);
    ASSERT_TRUE(defaults.contains(name)) << name;
    json request = {{name, other_value(info, defaults[name])}};
    if (name == "grade") request["hole_diameter"] = 8.0;  // grading sets diameters in mm
    const json changed = settings(options_from_json(request.dump()));
    for (const auto& [key, was] : defaults.items()) {
      if (request.contains(key)) continue;
      EXPECT_EQ(changed[key], was) << "setting " << name << " changed " << key;
    }
    EXPECT_NE(changed[name], defaults[name]) << name << " was not read";
  }
  EXPECT_EQ(find_option("no_such_option"), nullptr);
}

TEST(OptionTable, SettingsGoRoundUnchanged) {
  Options o;
  o.hole_diameter = 8;
  o.spacing = 14;
  o.grade = Grade{Grade::Kind::axis, 1, {}, {}, 7, 10, 0, "", false};
  o.keep_out = {{{1, 2, 3}, 4}};
  o.keep_out_boxes = {{{0, 0, 0}, {1, 2, 3}}};
  o.rim = 5;
  o.seed = 18446744073709551615ull;  // every bit of a 64-bit seed survives
  o.offset = WallOffset::outside;
  const std::string text = options_to_json(o);
  const Options back = options_from_json(text);
  EXPECT_EQ(options_to_json(back), text);
  EXPECT_EQ(back.seed, o.seed);
  // The paper's parameters, the other way of asking.
  Options paper;
  paper.alpha = 2200;
  paper.iso = {0.25, 0.0};
  paper.phi_bar = -0.25;
  EXPECT_EQ(options_to_json(options_from_json(options_to_json(paper))), options_to_json(paper));
  // A default that means "not given" (the rim's, the paper's model's) is null, or an empty list, both ways.
  const json defaults = settings(Options{});
  for (const char* name : {"rim", "alpha", "epsilon_m", "dt_h", "phi_bar"})
    EXPECT_TRUE(defaults[name].is_null()) << name;
  EXPECT_EQ(defaults["iso"], json::array());
  EXPECT_TRUE(std::isnan(options_from_json(R"({"rim": null, "alpha": null})").rim));
  EXPECT_TRUE(options_from_json(R"({"iso": []})").iso.empty());
  // Keep-outs as the studio sends them: [[x, y, z, r]].
  const Options studio = options_from_json(R"({"hole_diameter": 8, "keep_out": [[1, 2, 3, 4]]})");
  ASSERT_EQ(studio.keep_out.size(), 1u);
  EXPECT_EQ(studio.keep_out[0].radius, 4.0);
  EXPECT_EQ(studio.keep_out[0].centre[2], 3.0);
}

// A refusal names the option at fault (Error::option()) and says what it takes.
TEST(OptionTable, BadValuesAreRefusedNamingTheOption) {
  const auto refused = [](const std::string& text) -> std::pair<std::string, std::string> {
    try {
      options_from_json(text);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_option) << text;
      return {e.option(), e.what()};
    }
    ADD_FAILURE() << text << " was accepted";
    return {};
  };
  const auto [unknown, unknown_text] = refused(R"({"hole_diam": 8})");
  EXPECT_EQ(unknown, "hole_diam");
  EXPECT_NE(unknown_text.find("not an option"), std::string::npos) << unknown_text;
  const auto [type, type_text] = refused(R"({"spacing": "14"})");
  EXPECT_EQ(type, "spacing");
  EXPECT_NE(type_text.find("a number in mm, at least 0"), std::string::npos) << type_text;
  EXPECT_EQ(refused(R"({"resolution": 4})").first, "resolution");
  EXPECT_EQ(refused(R"({"resolution": 40.5})").first, "resolution");
  EXPECT_EQ(refused(R"({"porosity": -0.1})").first, "porosity");
  EXPECT_EQ(refused(R"({"mode": "solid"})").first, "mode");
  EXPECT_EQ(refused(R"({"keep_out": [[1, 2, 3]]})").first, "keep_out");
  EXPECT_EQ(refused(R"({"keep_out": [[1, 2, 3, 0]]})").first, "keep_out");  // validate()'s radius > 0
  EXPECT_EQ(refused(R"({"grade": {"kind": "spiral"}})").first, "grade");
  // The studio's and a project file's way in: holes in mm and a paper's parameter, even at its default.
  EXPECT_EQ(refused(R"({"hole_diameter": 8, "phi_bar": -0.3})").first, "phi_bar");
  EXPECT_EQ(refused(R"({"threads": -1})").first, "threads");
  EXPECT_EQ(refused(R"({"seed": 1e3})").first, "seed");
  EXPECT_NE(refused("[1, 2]").second.find("JSON object"), std::string::npos);
  EXPECT_NE(refused("{not json").second.find("not valid JSON"), std::string::npos);
}

// The library's own checks name the option they refuse (issue 48: a bad `spacing` was reported as
// `hole_diameter`).
TEST(OptionTable, ValidationNamesEachHoleLength) {
  for (const char* name : {"hole_diameter", "spacing", "porosity"}) {
    Options o;
    (std::string(name) == "hole_diameter" ? o.hole_diameter
     : std::string(name) == "spacing"     ? o.spacing
                                          : o.porosity) = -1.0;
    try {
      validate(o);
      ADD_FAILURE() << name;
    } catch (const Error& e) {
      EXPECT_EQ(e.option(), name);
    }
  }
}

// Sets the row's field to x (a list of one for the pore levels); false where its type cannot hold x
// exactly (a seed of -1) or the row holds no number.
bool set_number(Options& o, const OptionInfo& info, double x) {
  return std::visit(
      [&](auto member) {
        using T = std::remove_cvref_t<decltype(o.*member)>;
        if constexpr (std::is_same_v<T, std::vector<double>>) {
          o.*member = {x};
          return true;
        } else if constexpr (std::is_floating_point_v<T>) {
          o.*member = x;
          return true;
        } else if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
          // Only ends below 2^53 are tried, so that these bounds are exact as doubles.
          if (x < static_cast<double>(std::numeric_limits<T>::min()) ||
              x > static_cast<double>(std::numeric_limits<T>::max()))
            return false;
          o.*member = static_cast<T>(x);
          return true;
        } else {
          return false;
        }
      },
      info.field);
}

// Every finite end of every row's range, from the table: a value just outside is refused by validate()
// naming that option, and one just inside passes (validate() is no stricter than the table that the
// studio and the JSON read). Just outside a closed end is the next double, or the next integer; an open
// end is itself outside.
TEST(OptionTable, ValidateRefusesJustOutsideEachRangeAndTakesJustInside) {
  constexpr double kExact = 9007199254740992.0;  // 2^53
  int ends = 0;
  for (const OptionInfo& info : option_table()) {
    if (info.type != OptionType::number && info.type != OptionType::integer &&
        info.type != OptionType::numbers)
      continue;
    const bool integral = info.type == OptionType::integer;
    for (const int side : {-1, 1}) {
      const double end = side < 0 ? info.min : info.max;
      const bool open = side < 0 ? info.min_open : info.max_open;
      if (!std::isfinite(end) || std::abs(end) >= kExact) continue;
      const double step = side * std::numeric_limits<double>::infinity();
      const double outside = open ? end : integral ? end + side : std::nextafter(end, step);
      const double inside = !open ? end : integral ? end - side : std::nextafter(end, -step);
      std::ostringstream what_text;
      what_text << info.name << (side < 0 ? " below " : " above ") << end;
      const std::string what = what_text.str();
      Options bad;
      if (!set_number(bad, info, outside)) continue;
      ++ends;
      try {
        validate(bad);
        ADD_FAILURE() << what << ": " << outside << " was accepted";
      } catch (const Error& e) {
        EXPECT_EQ(e.option(), info.name) << what << ": " << e.what();
        EXPECT_NE(std::string(e.what()).find("`" + std::string(info.name) + "`"), std::string::npos)
            << e.what();
      }
      Options good;
      ASSERT_TRUE(set_number(good, info, inside)) << what;
      EXPECT_NO_THROW(validate(good)) << what << ": " << inside << " was refused";
    }
  }
  EXPECT_GE(ends, 30) << "the ranged rows' ends";
}

}  // namespace
}  // namespace poreshell
