// poreshell._poreshell: the Python binding of the public C++ API (include/poreshell/). The pure-Python
// part (python/poreshell/__init__.py) checks and converts numpy arguments and documents the API; this
// file builds the library's Input and (with options.cpp) Options from them, runs perforate() with the GIL
// released, and turns the Result into numpy arrays and the JSON report text.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "options.hpp"
#include "poreshell/poreshell.hpp"

namespace py = pybind11;

namespace {

static_assert(sizeof(poreshell::Point) == 3 * sizeof(double), "Point must be three packed doubles");
static_assert(sizeof(poreshell::Triangle) == 3 * sizeof(std::int32_t), "Triangle must be three packed ints");

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Ints = py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>;

// Thrown through the library from the progress callback when Python raised (the Python error is kept
// aside and raised again once the run has stopped). Not a std::exception, so no stage can swallow it.
struct CallbackAbort {};

// An input, opaque to Python (pybind11/stl.h would convert the variant itself to a Python object).
struct InputBox {
  poreshell::Input input;
};

// The library's messages name options by their API names, which are the keyword names here too, except
// the shape's size.
std::string python_message(std::string message) {
  const std::string from = "`radius_mm`", to = "`radius`";
  for (std::size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
    message.replace(at, from.size(), to);
  return message;
}

const char* code_name(poreshell::ErrorCode code) {
  switch (code) {
    case poreshell::ErrorCode::invalid_option:
      return "invalid_option";
    case poreshell::ErrorCode::invalid_input:
      return "invalid_input";
    case poreshell::ErrorCode::too_large:
      return "too_large";
    case poreshell::ErrorCode::cancelled:
      return "cancelled";
    case poreshell::ErrorCode::out_of_time:
      return "out_of_time";
    case poreshell::ErrorCode::io:
      return "io";
    case poreshell::ErrorCode::internal:
      return "internal";
  }
  return "internal";
}

// poreshell::Error -> ValueError (bad option or input) or RuntimeError (everything else), with the
// library's message and two attributes: `code` (the ErrorCode's name) and `option` (the API name, or "").
void raise_error(const poreshell::Error& e) {
  const bool bad_argument =
      e.code() == poreshell::ErrorCode::invalid_option || e.code() == poreshell::ErrorCode::invalid_input;
  py::handle type = bad_argument ? PyExc_ValueError : PyExc_RuntimeError;
  py::object exc = type(python_message(e.what()));
  exc.attr("code") = code_name(e.code());
  exc.attr("option") = e.option() == "radius_mm" ? std::string("radius") : e.option();
  PyErr_SetObject(type.ptr(), exc.ptr());
}

poreshell::Unit to_unit(const std::string& name) {
  static const std::map<std::string, poreshell::Unit> units{{"m", poreshell::Unit::m},
                                                            {"cm", poreshell::Unit::cm},
                                                            {"mm", poreshell::Unit::mm},
                                                            {"inch", poreshell::Unit::inch},
                                                            {"in", poreshell::Unit::inch}};
  const auto it = units.find(name);
  if (it == units.end())
    throw py::value_error("`units` must be 'm', 'cm', 'mm' or 'inch', got '" + name + "'");
  return it->second;
}

std::vector<poreshell::Point> to_points(const Doubles& array) {
  if (array.ndim() != 2 || array.shape(1) != 3)
    throw py::value_error("expected an (n, 3) array of coordinates");
  std::vector<poreshell::Point> points(static_cast<std::size_t>(array.shape(0)));
  if (!points.empty()) std::memcpy(points.data(), array.data(), points.size() * sizeof(poreshell::Point));
  return points;
}

std::vector<poreshell::Triangle> to_triangles(const Ints& array) {
  if (array.ndim() != 2 || array.shape(1) != 3) throw py::value_error("expected an (m, 3) array of indices");
  std::vector<poreshell::Triangle> triangles(static_cast<std::size_t>(array.shape(0)));
  if (!triangles.empty())
    std::memcpy(triangles.data(), array.data(), triangles.size() * sizeof(poreshell::Triangle));
  return triangles;
}

py::array_t<double> points_array(const std::vector<poreshell::Point>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  if (!points.empty())
    std::memcpy(out.mutable_data(), points.data(), points.size() * sizeof(poreshell::Point));
  return out;
}

py::array_t<std::int32_t> triangles_array(const std::vector<poreshell::Triangle>& triangles) {
  py::array_t<std::int32_t> out({static_cast<py::ssize_t>(triangles.size()), py::ssize_t{3}});
  if (!triangles.empty())
    std::memcpy(out.mutable_data(), triangles.data(), triangles.size() * sizeof(poreshell::Triangle));
  return out;
}

// --- The run ----------------------------------------------------------------------------------------------

struct RunState {
  py::object progress;                         // a callable (stage, fraction), or None
  std::optional<py::error_already_set> error;  // what Python raised: re-raised after the run (GIL held)
  std::atomic<bool> cancel{false};
};

py::dict holes_dict(const std::vector<poreshell::Hole>& holes) {
  const auto n = static_cast<py::ssize_t>(holes.size());
  py::array_t<double> centre({n, py::ssize_t{3}}), normal({n, py::ssize_t{3}});
  py::array_t<double> diameter(n), circularity(n), nearest(n), axis_ratio(n), asked(n);
  auto c = centre.mutable_unchecked<2>();
  auto nm = normal.mutable_unchecked<2>();
  auto d = diameter.mutable_unchecked<1>();
  auto ci = circularity.mutable_unchecked<1>();
  auto ne = nearest.mutable_unchecked<1>();
  auto ar = axis_ratio.mutable_unchecked<1>();
  auto as = asked.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const poreshell::Hole& h = holes[static_cast<std::size_t>(i)];
    for (py::ssize_t k = 0; k < 3; ++k) {
      c(i, k) = h.centre[static_cast<std::size_t>(k)];
      nm(i, k) = h.normal[static_cast<std::size_t>(k)];
    }
    d(i) = h.diameter;
    ci(i) = h.circularity;
    ne(i) = h.nearest;
    ar(i) = h.axis_ratio;
    as(i) = h.asked_diameter;
  }
  py::dict out;
  out["centre"] = centre;
  out["normal"] = normal;
  out["diameter"] = diameter;
  out["circularity"] = circularity;
  out["nearest"] = nearest;
  out["axis_ratio"] = axis_ratio;
  out["asked_diameter"] = asked;
  return out;
}

// Runs `perforate` (perforate() of an input or of a prepared one) on a thread of its own while this
// (the calling, usually main) thread waits with the GIL released, checking for signals every 50 ms:
// Ctrl-C sets the cancel flag, and the run stops within about half a second. The progress callback
// takes the GIL from the run's threads. Returns the outputs as arrays and the report as JSON.
// What the viewer page needs of a run besides its meshes, which live in the numpy arrays (one copy at a
// time): the C++ Result without its meshes, the Options and the Input (kept alive by `owner`).
struct ResultBox {
  poreshell::Result result;
  poreshell::Options options;
  const poreshell::Input* input = nullptr;
  py::object owner;
};

using Perforate = std::function<poreshell::Result(const poreshell::RunControl&)>;
py::tuple run_and_collect(const Perforate& perforate, const py::object& progress, double max_seconds,
                          const poreshell::Options& options, const poreshell::Input* input,
                          py::object owner) {
  RunState state;
  state.progress = progress;
  poreshell::RunControl control;
  control.cancel = &state.cancel;
  control.max_seconds = max_seconds;
  if (!progress.is_none()) {
    // Captures a pointer only: the RunControl is copied inside the run, without the GIL.
    control.progress = [s = &state](const poreshell::Progress& p) {
      py::gil_scoped_acquire gil;
      if (s->error) throw CallbackAbort{};
      try {
        s->progress(py::str(p.stage.data(), p.stage.size()), p.fraction);
      } catch (py::error_already_set& e) {
        s->error = std::move(e);
        s->cancel.store(true);
        throw CallbackAbort{};
      }
    };
  }

  poreshell::Result result;
  std::exception_ptr failure;
  {
    std::mutex mutex;
    std::condition_variable finished;
    bool done = false;
    py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        result = perforate(control);
      } catch (...) {
        failure = std::current_exception();
      }
      std::lock_guard lock(mutex);
      done = true;
      finished.notify_one();
    });
    std::unique_lock lock(mutex);
    while (!finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) {
      if (state.cancel.load()) continue;
      lock.unlock();
      {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) {
          if (!state.error) state.error = py::error_already_set();
          PyErr_Clear();
          state.cancel.store(true);
        }
      }
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (state.error) throw *state.error;  // the callback's exception or KeyboardInterrupt, unchanged
  if (failure) std::rethrow_exception(failure);

  const std::string report = poreshell::report_json(result.report, result.outputs);
  py::list outputs;
  for (poreshell::Output& out : result.outputs) {
    py::dict level;
    level["iso"] = out.iso;
    level["vertices"] = points_array(out.mesh.vertices);
    level["faces"] = triangles_array(out.mesh.triangles);
    level["holes"] = holes_dict(out.holes);
    if (!out.pattern.empty())
      level["pattern"] = py::array_t<double>(py::ssize_t(out.pattern.size()), out.pattern.data());
    out.mesh = {};  // one copy at a time
    outputs.append(level);
  }
  auto box = std::make_unique<ResultBox>();
  box->result = std::move(result);
  box->options = options;
  box->input = input;
  box->owner = std::move(owner);
  return py::make_tuple(outputs, report, std::move(box));
}

// The viewer page of output `output` (its mesh given back from the arrays) at `html`, and its picture at
// `png` when not empty (then `html` is a temporary page the caller removes).
void save_view(ResultBox& box, std::size_t output, const Doubles& vertices, const Ints& faces,
               const std::filesystem::path& html, const std::filesystem::path& png) {
  if (output >= box.result.outputs.size())
    throw py::value_error("the result has no output " + std::to_string(output));
  poreshell::Mesh& mesh = box.result.outputs[output].mesh;
  mesh = {to_points(vertices), to_triangles(faces)};
  poreshell::ViewOptions view;
  view.output = output;
  try {
    py::gil_scoped_release release;
    poreshell::save_html(html, box.result, box.options, box.input, view);
    if (!png.empty()) poreshell::save_png(html, png);
  } catch (...) {
    mesh = {};
    throw;
  }
  mesh = {};
}

py::tuple run(const py::object& input_object, const py::dict& kwargs, const py::object& progress,
              double max_seconds) {
  const InputBox& input = input_object.cast<const InputBox&>();
  const poreshell::Options options = poreshell_python::to_options(kwargs);
  return run_and_collect(
      [&](const poreshell::RunControl& control) {
        return poreshell::perforate(input.input, options, control);
      },
      progress, max_seconds, options, &input.input, input_object);
}

// An input placed with its options once (poreshell::prepare), for estimate_prepared and run_prepared.
// The input it points to is kept alive by the binding (py::keep_alive).
struct PreparedBox {
  poreshell::Prepared prepared;
  poreshell::Options options;  // for the viewer page
};

PreparedBox prepare(const InputBox& input, const py::dict& kwargs) {
  const poreshell::Options options = poreshell_python::to_options(kwargs, "prepare");
  py::gil_scoped_release release;
  return PreparedBox{poreshell::prepare(input.input, options), options};
}

py::tuple run_prepared(const py::object& box_object, const py::object& progress, double max_seconds) {
  const PreparedBox& box = box_object.cast<const PreparedBox&>();
  return run_and_collect(
      [&](const poreshell::RunControl& control) { return poreshell::perforate(box.prepared, control); },
      progress, max_seconds, box.options, box.prepared.input, box_object);
}

py::dict estimate_dict(const poreshell::Estimate& e) {
  py::dict out;
  out["size_mm"] = py::make_tuple(e.size_mm[0], e.size_mm[1], e.size_mm[2]);
  out["grid"] = py::make_tuple(e.grid[0], e.grid[1], e.grid[2]);
  out["voxel_size_mm"] = e.voxel_size_mm;
  out["band_voxels"] = e.band_voxels;
  out["seconds"] = e.seconds;
  out["peak_bytes"] = e.peak_bytes;
  out["triangles"] = e.triangles;
  out["stl_bytes"] = e.stl_bytes;
  out["preview"] = e.preview;
  out["ply_bytes"] = e.ply_bytes;
  out["warnings"] = e.warnings;
  return out;
}

// poreshell::estimate() as a dict, the GIL released while the input is placed (a large scan's tree).
py::dict estimate(const InputBox& input, const py::dict& kwargs) {
  const poreshell::Options options = poreshell_python::to_options(kwargs, "estimate");
  poreshell::Estimate e;
  {
    py::gil_scoped_release release;
    e = poreshell::estimate(input.input, options);
  }
  return estimate_dict(e);
}

py::dict estimate_prepared(const PreparedBox& box) {
  poreshell::Estimate e;
  {
    py::gil_scoped_release release;
    e = poreshell::estimate(box.prepared);
  }
  return estimate_dict(e);
}

}  // namespace

PYBIND11_MODULE(_poreshell, m) {
  m.doc() = "The C++ part of poreshell; use the functions of the poreshell package.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const poreshell::Error& e) {
      raise_error(e);
    } catch (const CallbackAbort&) {
      PyErr_SetString(PyExc_RuntimeError, "the run was cancelled by its progress callback");
    }
  });

  py::class_<InputBox>(m, "Input", "An input of the library: a mesh, a point cloud or a shape.");
  py::class_<PreparedBox>(m, "PreparedInput", "An input placed with its options (poreshell.prepare).");
  py::class_<ResultBox>(m, "RunResult", "What a Result's viewer page needs besides its meshes.");
  m.def("save_view", &save_view, py::arg("result"), py::arg("output"), py::arg("vertices"), py::arg("faces"),
        py::arg("html"), py::arg("png"));

  m.def(
      "mesh_input",
      [](const Doubles& vertices, const Ints& faces, const std::string& units, const std::string& name,
         const std::map<std::string, std::vector<double>>& fields) {
        poreshell::MeshInput in;
        in.mesh.vertices = to_points(vertices);
        in.mesh.triangles = to_triangles(faces);
        in.unit = to_unit(units);
        in.name = name;
        in.vertex_fields = fields;
        return InputBox{std::move(in)};
      },
      py::arg("vertices"), py::arg("faces"), py::arg("units"), py::arg("name"), py::arg("fields"));
  m.def(
      "points_input",
      [](const Doubles& points, const Ints& patches, const std::string& units, const std::string& name) {
        poreshell::PointsInput in;
        in.points = to_points(points);
        in.patches = to_triangles(patches);
        in.unit = to_unit(units);
        in.name = name;
        return InputBox{std::move(in)};
      },
      py::arg("points"), py::arg("patches"), py::arg("units"), py::arg("name"));
  m.def(
      "shape_input",
      [](const std::string& kind, double radius_mm, const std::string& units) {
        poreshell::ShapeInput in;
        if (kind == "sphere")
          in.kind = poreshell::ShapeKind::sphere;
        else if (kind == "torus")
          in.kind = poreshell::ShapeKind::torus;
        else
          throw py::value_error("unknown shape '" + kind + "': use sphere or torus");
        in.radius_mm = radius_mm;
        in.unit = to_unit(units);
        return InputBox{in};
      },
      py::arg("kind"), py::arg("radius_mm"), py::arg("units"));
  m.def(
      "file_mesh_input",
      [](const std::filesystem::path& path, const std::string& units,
         const std::vector<std::string>& fields) {
        return InputBox{poreshell::load_mesh(path, to_unit(units), fields)};
      },
      py::arg("path"), py::arg("units"), py::arg("fields"));
  m.def(
      "load_mesh",
      [](const std::filesystem::path& path, const std::string& units) {
        const poreshell::Unit unit = to_unit(units);
        poreshell::MeshInput in = poreshell::load_mesh(path, unit);
        const double scale = poreshell::millimetres_per(unit);
        if (scale != 1.0)
          for (poreshell::Point& p : in.mesh.vertices)
            for (double& x : p) x *= scale;
        return py::make_tuple(points_array(in.mesh.vertices), triangles_array(in.mesh.triangles));
      },
      py::arg("path"), py::arg("units"));
  m.def(
      "load_points",
      [](const std::filesystem::path& path) {
        poreshell::PointsInput in = poreshell::load_points(path);
        return py::make_tuple(points_array(in.points), triangles_array(in.patches));
      },
      py::arg("path"));
  m.def(
      "save_mesh",
      [](const std::filesystem::path& path, const Doubles& vertices, const Ints& faces, double iso,
         const std::optional<Doubles>& pattern) {
        poreshell::Output out;
        out.iso = iso;
        out.mesh.vertices = to_points(vertices);
        out.mesh.triangles = to_triangles(faces);
        if (pattern) out.pattern.assign(pattern->data(), pattern->data() + pattern->size());
        py::gil_scoped_release release;
        poreshell::save_mesh(path, out);
      },
      py::arg("path"), py::arg("vertices"), py::arg("faces"), py::arg("iso") = 0.0,
      py::arg("pattern") = std::nullopt);
  m.def("check_mesh_path", [](const std::filesystem::path& path) { poreshell::check_mesh_path(path); });
  m.def("check_output_path", [](const std::filesystem::path& path) { poreshell::check_output_path(path); });
  m.def("option_names", &poreshell_python::option_names);
  m.def("estimate", &estimate, py::arg("input"), py::arg("options"));
  m.def("prepare", &prepare, py::arg("input"), py::arg("options"), py::keep_alive<0, 1>());
  m.def("estimate_prepared", &estimate_prepared, py::arg("prepared"));
  m.def("perforate_prepared", &run_prepared, py::arg("prepared"), py::arg("progress"),
        py::arg("max_seconds"));
  m.def("perforate", &run, py::arg("input"), py::arg("options"), py::arg("progress"), py::arg("max_seconds"));
  m.def("version", [] { return std::string(poreshell::version()); });
}
