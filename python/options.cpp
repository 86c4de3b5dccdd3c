// Options of the library from perforate()'s keyword arguments, each checked and converted by its API name
// (the binding, poreshell_module.cpp, uses to_options; option_names lists the keywords).

#include "options.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

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

using Setter = std::function<void(poreshell::Options&, const std::string&, py::handle)>;

Setter set_double(double poreshell::Options::*field) {
  return [field](poreshell::Options& o, const std::string& n, py::handle v) { o.*field = to_double(n, v); };
}
template <typename Int>
Setter set_int(Int poreshell::Options::*field) {
  return [field](poreshell::Options& o, const std::string& n, py::handle v) { o.*field = to_int<Int>(n, v); };
}
template <typename Enum>
Setter set_enum(Enum poreshell::Options::*field) {
  return
      [field](poreshell::Options& o, const std::string& n, py::handle v) { o.*field = to_enum<Enum>(n, v); };
}

// Every field of poreshell::Options, by its API name.
const std::map<std::string, Setter>& setters() {
  using O = poreshell::Options;
  static const std::map<std::string, Setter> table{
      {"hole_diameter", set_double(&O::hole_diameter)},
      {"spacing", set_double(&O::spacing)},
      {"porosity", set_double(&O::porosity)},
      {"grade", [](O& o, const std::string&, py::handle v) { o.grade = to_grade(v); }},
      {"resolution", set_int(&O::resolution)},
      {"voxel_size", set_double(&O::voxel_size)},
      {"mode", set_enum(&O::mode)},
      {"wall", set_double(&O::wall)},
      {"offset", set_enum(&O::offset)},
      {"rim", set_double(&O::rim)},
      {"thin_feature_ratio", set_double(&O::thin_feature_ratio)},
      {"crease_angle", set_double(&O::crease_angle)},
      {"keep_out",
       [](O& o, const std::string& n, py::handle v) {
         o.keep_out.clear();
         for (const auto& r : to_rows(n, v, 4)) o.keep_out.push_back({{r[0], r[1], r[2]}, r[3]});
       }},
      {"keep_out_boxes",
       [](O& o, const std::string& n, py::handle v) {
         o.keep_out_boxes.clear();
         for (const auto& r : to_rows(n, v, 6))
           o.keep_out_boxes.push_back({{r[0], r[1], r[2]}, {r[3], r[4], r[5]}});
       }},
      {"keep_out_mask", [](O& o, const std::string& n, py::handle v) { o.keep_out_mask = to_string(n, v); }},
      {"max_triangles", set_int(&O::max_triangles)},
      {"max_deviation", set_double(&O::max_deviation)},
      {"keep_fragments", [](O& o, const std::string& n, py::handle v) { o.keep_fragments = to_bool(n, v); }},
      {"min_part_fraction", set_double(&O::min_part_fraction)},
      {"scale", set_double(&O::scale)},
      {"preview", [](O& o, const std::string& n, py::handle v) { o.preview = to_bool(n, v); }},
      {"alpha", set_double(&O::alpha)},
      {"epsilon_m", set_double(&O::epsilon_m)},
      {"dt_h", set_double(&O::dt_h)},
      {"phi_bar", set_double(&O::phi_bar)},
      {"iso",
       [](O& o, const std::string& n, py::handle v) {
         o.iso.clear();
         if (py::isinstance<py::sequence>(v) && !py::isinstance<py::str>(v)) {
           for (py::handle item : py::reinterpret_borrow<py::sequence>(v))
             o.iso.push_back(to_double(n, item));
           if (o.iso.empty()) bad_value(n, "a level or a non-empty sequence of levels", v);
         } else {
           o.iso.push_back(to_double(n, v));
         }
       }},
      {"initial_amplitude", set_double(&O::initial_amplitude)},
      {"seed", set_int(&O::seed)},
      {"tolerance", set_double(&O::tolerance)},
      {"max_steps", set_int(&O::max_steps)},
      {"stop", set_enum(&O::stop)},
      {"layout", set_enum(&O::layout)},
      {"solver", set_enum(&O::solver)},
      {"fast_tolerance", set_double(&O::fast_tolerance)},
      {"min_stabilisation", set_double(&O::min_stabilisation)},
      {"coarse_start", [](O& o, const std::string& n, py::handle v) { o.coarse_start = to_bool(n, v); }},
      {"inner", set_enum(&O::inner)},
      {"inner_tolerance", set_double(&O::inner_tolerance)},
      {"energy_every", set_int(&O::energy_every)},
      {"point_route", set_enum(&O::point_route)},
      {"max_memory_gb", set_double(&O::max_memory_gb)},
      {"threads", set_int(&O::threads)},
  };
  return table;
}

}  // namespace

poreshell::Options to_options(const py::dict& kwargs, const std::string& caller) {
  poreshell::Options options;
  for (const auto& [key_handle, value] : kwargs) {
    const std::string key = py::str(key_handle);
    const auto it = setters().find(key);
    if (it == setters().end())
      throw py::type_error(caller + "() got an unexpected keyword argument '" + key + "'");
    if (!value.is_none()) it->second(options, key, value);
  }
  // As the CLI: with holes asked in mm, the hole map chooses the model, which may then not be given
  // (Options cannot tell a default from a value given).
  for (const char* hole : {"hole_diameter", "spacing", "porosity"}) {
    if (!kwargs.contains(hole) || kwargs[hole].is_none()) continue;
    for (const char* model : {"alpha", "epsilon_m", "dt_h", "phi_bar", "iso"})
      if (kwargs.contains(model) && !kwargs[model].is_none())
        throw py::value_error(std::string("`") + model + "` cannot be given with `" + hole +
                              "`: the hole map chooses it from the holes in mm");
  }
  poreshell::validate(options);
  return options;
}

std::vector<std::string> option_names() {
  std::vector<std::string> names;
  for (const auto& [name, unused] : setters()) names.push_back(name);
  return names;
}

}  // namespace poreshell_python
