#include "geometry/printability.hpp"

#include "core/error.hpp"

namespace poreshell {

std::string printability_failures(const MeshTopology& t) {
  std::string failed;
  const auto fail = [&](std::int64_t count, const char* what) {
    if (count != 0) failed += (failed.empty() ? "" : ", ") + std::to_string(count) + " " + what;
  };
  fail(t.boundary_edges, "boundary edges");
  fail(t.nonmanifold_edges + t.nonmanifold_vertices, "non-manifold edges or vertices");
  fail(t.misoriented_edges, "inconsistently oriented edges");
  fail(t.degenerate_triangles, "degenerate triangles");
  if (!(t.signed_volume > 0.0)) failed += (failed.empty() ? "" : ", ") + std::string("volume not positive");
  return failed;
}

void check_printable(const MeshTopology& t, double iso) {
  const std::string at = "the solid at iso " + std::to_string(iso);
  if (t.triangles == 0)
    throw Error(ErrorCode::invalid_option, at + " is empty: choose a level above min(phi)", "iso");
  const std::string failed = printability_failures(t);
  if (!failed.empty())
    throw Error(ErrorCode::internal, at + " failed the printability check (" + failed +
                                         "); nothing was written. Please report this as a bug");
}

}  // namespace poreshell
