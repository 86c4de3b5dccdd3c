// MeshSurface's nearest-triangle search (geometry/mesh_surface.cpp, the band's near field and every
// mesh query) against Embree 3's point query with the same double-precision closest-point test in its
// callback, both in this process on the same points: the grid points within the band's reach of the
// bunny at the preview's grid (8 mm holes at 14 mm: h = 1.15 mm, reach 4.4 h), in the order the near
// field visits them (x fastest), on 1 and 2 threads. Prints the time of each and the largest
// difference of the distances found.
// Usage: bench_mesh_distance_vs_embree [mesh.obj] [h_mm] [reach_h]
// Figures and the conclusion: docs/benchmarks.md, "Mesh distance against Embree".

#include <embree3/rtcore.h>
#include <fmt/core.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "geometry/mesh_surface.hpp"
#include "io/mesh_io.hpp"

namespace {

using poreshell::MeshSurface;
using poreshell::TriangleMesh;
using poreshell::Vec3;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct EmbreeMesh {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  const TriangleMesh* mesh = nullptr;
};

struct Nearest {
  const TriangleMesh* mesh;
  Vec3 p;
  double d2 = std::numeric_limits<double>::infinity();
};

bool visit_triangle(RTCPointQueryFunctionArguments* args) {
  auto* n = static_cast<Nearest*>(args->userPtr);
  const auto& t = n->mesh->triangles[args->primID];
  const Vec3 q = poreshell::closest_point_on_triangle(n->p, n->mesh->vertices[t[0]], n->mesh->vertices[t[1]],
                                                      n->mesh->vertices[t[2]]);
  const double d2 = (q - n->p).squaredNorm();
  if (!(d2 < n->d2)) return false;
  n->d2 = d2;
  // Float boxes of float vertices: a little slack keeps the search exact for the double triangles.
  args->query->radius = static_cast<float>(std::sqrt(d2) * (1.0 + 1e-5) + 1e-6);
  return true;
}

EmbreeMesh build_embree(const TriangleMesh& mesh) {
  EmbreeMesh e;
  e.mesh = &mesh;
  e.device = rtcNewDevice(nullptr);
  e.scene = rtcNewScene(e.device);
  RTCGeometry geometry = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int a = 0; a < 3; ++a) v[3 * i + a] = static_cast<float>(mesh.vertices[i][a]);
  auto* f = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int a = 0; a < 3; ++a) f[3 * i + a] = static_cast<unsigned>(mesh.triangles[i][a]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(e.scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(e.scene);
  return e;
}

double embree_distance(const EmbreeMesh& e, const Vec3& p) {
  RTCPointQuery query;
  query.x = static_cast<float>(p.x());
  query.y = static_cast<float>(p.y());
  query.z = static_cast<float>(p.z());
  query.radius = std::numeric_limits<float>::infinity();
  query.time = 0.0f;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  Nearest n{e.mesh, p};
  rtcPointQuery(e.scene, &query, &context, visit_triangle, &n);
  return std::sqrt(n.d2);
}

// Grid points of spacing h within `reach` of the surface, x fastest (as the near field asks them).
std::vector<Vec3> near_points(const MeshSurface& surface, double h, double reach) {
  const poreshell::Box box = surface.bounds();
  const Vec3 lo = box.min - Vec3::Constant(reach), hi = box.max + Vec3::Constant(reach);
  const int nx = static_cast<int>((hi.x() - lo.x()) / h) + 1,
            ny = static_cast<int>((hi.y() - lo.y()) / h) + 1,
            nz = static_cast<int>((hi.z() - lo.z()) / h) + 1;
  std::vector<std::vector<Vec3>> rows(static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz));
  tbb::parallel_for(std::size_t{0}, rows.size(), [&](std::size_t r) {
    const int j = static_cast<int>(r % static_cast<std::size_t>(ny)),
              k = static_cast<int>(r / static_cast<std::size_t>(ny));
    for (int i = 0; i < nx; ++i) {
      const Vec3 p = lo + h * Vec3(i, j, k);
      if (surface.distance(p) < reach) rows[r].push_back(p);
    }
  });
  std::vector<Vec3> points;
  for (const auto& row : rows) points.insert(points.end(), row.begin(), row.end());
  return points;
}

template <class Distance>
double timed(const std::vector<Vec3>& points, std::vector<double>& out, const Distance& distance) {
  const auto t0 = Clock::now();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) out[i] = distance(points[i]);
  });
  return seconds_since(t0);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "data/stanford-bunny.obj";
  const double h = argc > 2 ? std::stod(argv[2]) : 1.1533;
  const double reach_h = argc > 3 ? std::stod(argv[3]) : 4.4;
  TriangleMesh mesh = poreshell::read_triangle_mesh(path);
  for (Vec3& v : mesh.vertices) v *= 1000.0;  // the bunny is in metres: millimetres here

  auto t0 = Clock::now();
  const MeshSurface surface(mesh);
  const double build_ours = seconds_since(t0);
  t0 = Clock::now();
  const EmbreeMesh embree = build_embree(mesh);
  const double build_embree_s = seconds_since(t0);
  const std::vector<Vec3> points = near_points(surface, h, reach_h * h);
  fmt::print("{}: {} triangles; {} grid points within {:.1f} h of it (h = {:.3f} mm)\n", path,
             mesh.triangles.size(), points.size(), reach_h, h);
  fmt::print("build: MeshSurface {:.3f} s, Embree {:.3f} s\n", build_ours, build_embree_s);
  std::vector<double> ours(points.size()), theirs(points.size());
  for (const int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    double best_ours = 1e9, best_embree = 1e9;
    for (int round = 0; round < 3; ++round) {  // in turn, best of 3: the machine's speed drifts
      best_ours =
          std::min(best_ours, timed(points, ours, [&](const Vec3& p) { return surface.distance(p); }));
      best_embree = std::min(
          best_embree, timed(points, theirs, [&](const Vec3& p) { return embree_distance(embree, p); }));
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) worst = std::max(worst, std::abs(ours[i] - theirs[i]));
    fmt::print(
        "{} thread(s): MeshSurface {:.3f} s, Embree {:.3f} s, Embree / MeshSurface {:.2f}; largest "
        "difference {:.2e} mm\n",
        threads, best_ours, best_embree, best_embree / best_ours, worst);
  }
  rtcReleaseScene(embree.scene);
  rtcReleaseDevice(embree.device);
  return 0;
}
