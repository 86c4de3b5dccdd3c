// Issue 48: one option table that the report's `settings`, project files and the studio read. Every
// row reads and writes its own field, the JSON goes round unchanged, and a bad value is refused naming
// its option.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

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
      return now.is_null() ? json(3.0) : json(now.get<double>() == 0.5 ? 0.25 : 0.5);
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
  o.iso = {0.25, 0.0};
  o.seed = 18446744073709551615ull;  // every bit of a 64-bit seed survives
  o.offset = WallOffset::outside;
  const std::string text = options_to_json(o);
  const Options back = options_from_json(text);
  EXPECT_EQ(options_to_json(back), text);
  EXPECT_EQ(back.seed, o.seed);
  // The rim's default (not given) is null both ways.
  EXPECT_TRUE(settings(Options{})["rim"].is_null());
  EXPECT_TRUE(std::isnan(options_from_json(R"({"rim": null})").rim));
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

}  // namespace
}  // namespace poreshell
