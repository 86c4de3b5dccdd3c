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

Result perforate(const Input& input, const Options& options, const RunControl& control) {
  validate(options);
  RunMonitor monitor(control);
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  Result result;
  try {
    arena.execute([&] {
      PipelineResult run = run_pipeline(input, options, monitor);
      result.report = make_report(run, options);
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
                                 0.0});
        for (const HoleRecord& h : level.hole_table.holes)
          out.holes.push_back({{h.centre.x(), h.centre.y(), h.centre.z()},
                               {h.normal.x(), h.normal.y(), h.normal.z()},
                               h.diameter,
                               h.circularity,
                               h.nearest,
                               h.axis_ratio});
        result.outputs.push_back(std::move(out));
      }
    });
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(ErrorCode::too_large,
                "out of memory: ask for a coarser `voxel_size` or `resolution`, or larger holes");
  } catch (const std::invalid_argument& e) {
    throw Error(ErrorCode::internal, std::string(e.what()) + "; please report this as a bug");
  }
  return result;
}

}  // namespace poreshell
