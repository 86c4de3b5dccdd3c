// Options of the library from perforate()'s keyword arguments, by the option table's names and types
// (the binding, poreshell_module.cpp, uses to_options; option_names lists the keywords).

#include "options.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "poreshell/option_table.hpp"
#include "poreshell/poreshell.hpp"

namespace py = pybind11;

namespace poreshell_python {
namespace {

[[noreturn]] void bad_value(const std::string& name, const std::string& what, py::handle value) {
  throw py::value_error("`" + name + "` must be " + what + ", got " + py::repr(value).cast<std::string>());
}

double to_double(const std::string& name, py::handle value) {
  if (!py::isinstance<py::float_>(value) && !py::isinstance<py::int_>(value) &&
      !py::hasattr(value, "__float__"))
    bad_value(name, "a number", value);
  if (py::isinstance<py::bool_>(value)) bad_value(name, "a number", value);
  try {
    return value.cast<double>();
  } catch (const py::cast_error&) {
    bad_value(name, "a number", value);
  }
}

template <typename Int>
Int to_int(const std::string& name, py::handle value) {
  if (py::isinstance<py::bool_>(value) || py::isinstance<py::float_>(value))
    bad_value(name, "an integer", value);
  try {
    return value.cast<Int>();
  } catch (const py::cast_error&) {
    bad_value(name, "an integer in range", value);
  }
}

bool to_bool(const std::string& name, py::handle value) {
  if (!py::isinstance<py::bool_>(value)) bad_value(name, "True or False", value);
  return value.cast<bool>();
}

std::string to_string(const std::string& name, py::handle value) {
  if (!py::isinstance<py::str>(value)) bad_value(name, "a string", value);
  return value.cast<std::string>();
}

template <typename Enum>
Enum to_enum(const std::string& name, py::handle value) {
  std::string text = to_string(name, value);
  std::replace(text.begin(), text.end(), '-', '_');
  if (const std::optional<Enum> e = poreshell::enum_from_name<Enum>(text)) return *e;
  std::string names;
  for (const auto& entry : poreshell::enum_names(Enum{}))
    names += (names.empty() ? "'" : ", '") + std::string(entry.name) + "'";
  bad_value(name, "one of " + names, value);
}

std::vector<double> to_numbers(const std::string& name, py::handle value, std::size_t count) {
  const std::string what = "a sequence of " + std::to_string(count) + " numbers";
  if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value)) bad_value(name, what, value);
  const auto seq = py::reinterpret_borrow<py::sequence>(value);
  if (seq.size() != count) bad_value(name, what, value);
  std::vector<double> out;
  for (py::handle item : seq) out.push_back(to_double(name, item));
  return out;
}

poreshell::Point to_point(const std::string& name, py::handle value) {
  const std::vector<double> v = to_numbers(name, value, 3);
  return {v[0], v[1], v[2]};
}

// A sequence of `count`-tuples (or an (n, count) array).
std::vector<std::vector<double>> to_rows(const std::string& name, py::handle value, std::size_t count) {
  if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value)) {
    if (py::isinstance<py::array>(value)) return to_rows(name, value.attr("tolist")(), count);
    bad_value(name, "a sequence of " + std::to_string(count) + "-tuples", value);
  }
  std::vector<std::vector<double>> rows;
  for (py::handle row : py::reinterpret_borrow<py::sequence>(value))
    rows.push_back(to_numbers(name, row, count));
  return rows;
}

poreshell::Grade to_grade(py::handle value) {
  if (py::isinstance<py::str>(value)) return poreshell::parse_grade(value.cast<std::string>());
  if (!py::isinstance<py::dict>(value))
    bad_value("grade", "a spec string such as 'axis:z:4:8' or a dict", value);
  poreshell::Grade grade;
  for (const auto& [key_handle, item] : py::reinterpret_borrow<py::dict>(value)) {
    const std::string key = py::str(key_handle);
    const std::string name = "grade[" + key + "]";
    if (key == "kind") {
      grade.kind = to_enum<poreshell::Grade::Kind>(name, item);
    } else if (key == "axis") {
      if (py::isinstance<py::str>(item)) {
        const std::string axis = to_string(name, item);
        if (axis != "x" && axis != "y" && axis != "z") bad_value(name, "one of 'x', 'y', 'z'", item);
        grade.axis = axis[0] - 'x';
      } else
        grade.axis = to_int<int>(name, item);
    } else if (key == "from") {
      grade.from = to_point(name, item);
    } else if (key == "to") {
      grade.to = to_point(name, item);
    } else if (key == "from_diameter") {
      grade.from_diameter = to_double(name, item);
    } else if (key == "to_diameter") {
      grade.to_diameter = to_double(name, item);
    } else if (key == "radius") {
      grade.radius = to_double(name, item);
    } else if (key == "field") {
      grade.field = to_string(name, item);
    } else if (key == "mapped") {
      grade.mapped = to_bool(name, item);
    } else {
      throw py::value_error("`grade` has no key '" + key +
                            "': use kind, axis, from, to, from_diameter, to_diameter, radius, field, mapped");
    }
  }
  return grade;
}

// A keyword's value as the option table's JSON (include/poreshell/option_table.hpp), with what Python
// callers may pass besides: numpy arrays, one iso level alone, a grading spec string, axes as letters.
nlohmann::json to_json(const poreshell::OptionInfo& info, py::handle value) {
  const std::string name(info.name);
  using poreshell::OptionType;
  switch (info.type) {
    case OptionType::number:
      return to_double(name, value);
    case OptionType::integer:
      if (py::isinstance<py::int_>(value) && value.cast<py::int_>() >= py::int_(0))
        return to_int<std::uint64_t>(name, value);
      return to_int<std::int64_t>(name, value);
    case OptionType::boolean:
      return to_bool(name, value);
    case OptionType::choice: {
      std::string text = to_string(name, value);
      std::replace(text.begin(), text.end(), '-', '_');
      return text;
    }
    case OptionType::text:
      return to_string(name, value);
    case OptionType::numbers: {
      if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value))
        return {to_double(name, value)};
      nlohmann::json list = nlohmann::json::array();
      for (py::handle item : py::reinterpret_borrow<py::sequence>(value))
        list.push_back(to_double(name, item));
      if (list.empty()) bad_value(name, "a level or a non-empty sequence of levels", value);
      return list;
    }
    case OptionType::spheres:
      return to_rows(name, value, 4);
    case OptionType::boxes:
      return to_rows(name, value, 6);
    case OptionType::grade:  // set as a Grade by to_options, not through JSON
      break;
  }
  return nullptr;
}

}  // namespace

poreshell::Options to_options(const py::dict& kwargs, const std::string& caller) {
  // Each keyword by the option table, the whole read and validated as every front end's options are.
  // The grading, which Python may give as a spec string or a dict with axes as letters, becomes a Grade
  // here and is set after: the table's JSON of it would be a second writer of the report's object.
  nlohmann::json settings = nlohmann::json::object();
  std::optional<poreshell::Grade> grade;
  for (const auto& [key_handle, value] : kwargs) {
    const std::string key = py::str(key_handle);
    const poreshell::OptionInfo* info = poreshell::find_option(key);
    if (!info) throw py::type_error(caller + "() got an unexpected keyword argument '" + key + "'");
    if (value.is_none()) continue;
    if (info->type == poreshell::OptionType::grade)
      grade = to_grade(value);
    else
      settings[key] = to_json(*info, value);
  }
  poreshell::Options options = poreshell::options_from_json(settings.dump());
  if (grade) {
    options.grade = std::move(grade);
    poreshell::validate(options);
  }
  return options;
}

std::vector<std::string> option_names() {
  std::vector<std::string> names;
  for (const poreshell::OptionInfo& info : poreshell::option_table()) names.emplace_back(info.name);
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace poreshell_python
