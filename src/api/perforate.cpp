// The public API's entry point: options checked, the pipeline run in its own oneTBB arena (so that the
// thread count is per run and concurrent runs do not share state), and its result converted to the
// public types.

#include <tbb/task_arena.h>

#include <exception>
#include <new>

#include "core/error.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/report.hpp"
#include "poreshell/poreshell.hpp"

namespace poreshell {
namespace {

Mesh to_public(const TriangleMesh& mesh) {
  Mesh out;
  out.vertices.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) out.vertices.push_back({v.x(), v.y(), v.z()});
  out.triangles.assign(mesh.triangles.begin(), mesh.triangles.end());
  return out;
}

}  // namespace

const char* version() {
  return PORESHELL_VERSION;
}

namespace {

// Runs f in an arena of the options' thread count (so that the count is per run and concurrent runs do
// not share state), with the library's failures as Error.
template <class F>
void in_arena(const Options& options, const F& f) {
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  try {
    arena.execute(f);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(ErrorCode::too_large,
                "out of memory: ask for a coarser `voxel_size` or `resolution`, or larger holes");
  } catch (const std::invalid_argument& e) {
    throw Error(ErrorCode::internal, std::string(e.what()) + "; please report this as a bug");
  }
}

// The run from a prepared input, or (without one) preparing it first as the input stage's start.
Result run_and_convert(const Input& input, const Options& options, const PreparedInput* prepared,
                       const RunControl& control) {
  RunMonitor monitor(control);
  Result result;
  in_arena(options, [&] {
    PipelineResult run;
    if (prepared) {
      run = run_pipeline(input, *prepared, monitor);
    } else {
      monitor.stage("input");
      run = run_pipeline(input, prepare_input(input, options), monitor);
    }
    result.report = make_report(run, options);
    // Each hole's asked diameter at its centre: the grading's, or the request's.
    const auto asked_at = [&](const Vec3& x) {
      return run.grading && run.grading->asked_diameter ? run.grading->asked_diameter(x)
             : run.plan                                 ? run.plan->diameter
                                                        : 0.0;
    };
    for (MeshOutput& level : run.meshes) {
      Output out;
      out.iso = level.iso;
      out.mesh = to_public(level.mesh);
      level.mesh = {};  // one copy at a time: meshes run to gigabytes
      out.pattern = std::move(level.pattern);
      // A preview has no wall to measure: its holes are the band's spots (no circularity).
      if (options.preview)
        for (const BandHole& h : level.holes.holes)
          out.holes.push_back({{h.centre.x(), h.centre.y(), h.centre.z()},
                               {h.normal.x(), h.normal.y(), h.normal.z()},
                               h.diameter,
                               0.0,
                               h.nearest,
                               0.0,
                               asked_at(h.centre)});
      for (const HoleRecord& h : level.hole_table.holes)
        out.holes.push_back({{h.centre.x(), h.centre.y(), h.centre.z()},
                             {h.normal.x(), h.normal.y(), h.normal.z()},
                             h.diameter,
                             h.circularity,
                             h.nearest,
                             h.axis_ratio,
                             asked_at(h.centre)});
      result.outputs.push_back(std::move(out));
    }
  });
  return result;
}

}  // namespace

Prepared prepare(const Input& input, const Options& options) {
  validate(options);
  Prepared prepared;
  prepared.input = &input;
  in_arena(options,
           [&] { prepared.state = std::make_shared<const PreparedInput>(prepare_input(input, options)); });
  return prepared;
}

Result perforate(const Prepared& prepared, const RunControl& control) {
  if (!prepared.input || !prepared.state)
    throw Error(ErrorCode::invalid_option, "perforate: the Prepared was not made by prepare()");
  return run_and_convert(*prepared.input, prepared.state->given, prepared.state.get(), control);
}

Result perforate(const Input& input, const Options& options, const RunControl& control) {
  validate(options);
  return run_and_convert(input, options, nullptr, control);
}

}  // namespace poreshell
