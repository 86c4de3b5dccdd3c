// The wall probes' ray casting (measure/wall_measure.cpp) against Embree 3, both in this process: 128
// probes (256 rays) across a thick spherical shell of about 2 M triangles, the size of the bunny's
// shell at the default resolution. Time and peak memory of each, and the walls they measure.
// Usage: bench_wall_rays_vs_embree [threads] [slices]   (defaults: 2 threads, 1000 slices: 2.0 M triangles)
// Figures and the conclusion: docs/benchmarks.md, "Wall probes against Embree".

#include <embree3/rtcore.h>
#include <fmt/core.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "geometry/mesh.hpp"
#include "measure/wall_measure.hpp"

namespace {

using poreshell::TriangleMesh;
using poreshell::Vec3;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Peak resident memory since the last reset, in MB (Linux: writing 5 to clear_refs resets VmHWM).
void reset_peak() {
  std::ofstream("/proc/self/clear_refs") << "5";
}
double status_mb(const std::string& field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field + ":", 0) == 0) return std::stod(line.substr(field.size() + 1)) / 1024.0;
  return 0.0;
}

// A UV sphere of radius r, outward (or inward) oriented.
void add_sphere(TriangleMesh& mesh, double r, int slices, int stacks, bool inward) {
  const auto first = static_cast<std::int32_t>(mesh.vertices.size());
  mesh.vertices.push_back({0, 0, r});
  for (int s = 1; s < stacks; ++s) {
    const double theta = std::numbers::pi * s / stacks;
    for (int k = 0; k < slices; ++k) {
      const double phi = 2 * std::numbers::pi * k / slices;
      mesh.vertices.push_back(
          {r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi), r * std::cos(theta)});
    }
  }
  mesh.vertices.push_back({0, 0, -r});
  const auto ring = [&](int s, int k) { return first + 1 + (s - 1) * slices + (k % slices); };
  const auto add = [&](std::int32_t a, std::int32_t b, std::int32_t c) {
    mesh.triangles.push_back(inward ? std::array{a, c, b} : std::array{a, b, c});
  };
  const std::int32_t bottom = static_cast<std::int32_t>(mesh.vertices.size()) - 1;
  for (int k = 0; k < slices; ++k) {
    add(first, ring(1, k), ring(1, k + 1));
    for (int s = 1; s + 1 < stacks; ++s) {
      add(ring(s, k), ring(s + 1, k), ring(s + 1, k + 1));
      add(ring(s, k), ring(s + 1, k + 1), ring(s, k + 1));
    }
    add(bottom, ring(stacks - 1, k + 1), ring(stacks - 1, k));
  }
}

std::atomic<long long> embree_bytes{0}, embree_peak{0};
bool monitor(void*, ssize_t bytes, bool) {
  const long long now = embree_bytes += bytes;
  long long peak = embree_peak.load();
  while (now > peak && !embree_peak.compare_exchange_weak(peak, now)) {
  }
  return true;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::stoi(argv[1]) : 2;
  const int slices = argc > 2 ? std::stoi(argv[2]) : 1000;
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
  TriangleMesh mesh;  // a wall 0.2 thick between radii 0.8 and 1
  add_sphere(mesh, 1.0, slices, slices / 2 + 1, false);
  add_sphere(mesh, 0.8, slices, slices / 2 + 1, true);
  std::mt19937_64 rng(17);
  std::normal_distribution<double> gauss;
  std::vector<poreshell::WallProbe> probes(128);
  for (auto& p : probes) {
    const Vec3 n = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    p = {0.9 * n, n};
  }
  const double max_length = 0.5;
  fmt::print("shell of {} triangles, {} vertices; {} rays; {} threads\n", mesh.triangles.size(),
             mesh.vertices.size(), 2 * probes.size(), threads);

  reset_peak();
  double rss0 = status_mb("VmRSS");
  auto t0 = Clock::now();
  const poreshell::WallMeasurement ours = poreshell::measure_wall(mesh, probes, max_length);
  const double ours_s = seconds_since(t0);
  const double ours_mb = status_mb("VmHWM") - rss0;

  reset_peak();
  rss0 = status_mb("VmRSS");
  t0 = Clock::now();
  const std::string config = "threads=" + std::to_string(threads);
  RTCDevice device = rtcNewDevice(config.c_str());
  rtcSetDeviceMemoryMonitorFunction(device, monitor, nullptr);
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int a = 0; a < 3; ++a)
      v[3 * i + static_cast<std::size_t>(a)] = static_cast<float>(mesh.vertices[i][a]);
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (std::size_t c = 0; c < 3; ++c) idx[3 * f + c] = static_cast<unsigned>(mesh.triangles[f][c]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  const double build_s = seconds_since(t0);
  t0 = Clock::now();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::vector<double> walls;
  for (const auto& p : probes) {
    double wall = 0.0;
    bool both = true;
    for (const double sign : {1.0, -1.0}) {
      RTCRayHit rh{};
      rh.ray.org_x = static_cast<float>(p.start.x());
      rh.ray.org_y = static_cast<float>(p.start.y());
      rh.ray.org_z = static_cast<float>(p.start.z());
      rh.ray.dir_x = static_cast<float>(sign * p.normal.x());
      rh.ray.dir_y = static_cast<float>(sign * p.normal.y());
      rh.ray.dir_z = static_cast<float>(sign * p.normal.z());
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = static_cast<float>(max_length);
      rh.ray.mask = 0xFFFFFFFFu;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rh);
      both = both && rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      wall += rh.ray.tfar;
    }
    if (both) walls.push_back(wall);
  }
  const double query_s = seconds_since(t0);
  const double embree_mb = status_mb("VmHWM") - rss0;
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);

  fmt::print("  {:<22}{:>10}{:>14}{:>12}{:>10}\n", "", "time (s)", "peak RSS (MB)", "probes hit", "median");
  fmt::print("  {:<22}{:>10.3f}{:>14.1f}{:>12}{:>10.5f}\n", "measure_wall (ours)", ours_s, ours_mb,
             ours.probes, ours.median);
  fmt::print("  {:<22}{:>10.3f}{:>14.1f}{:>12}{:>10.5f}\n", "Embree build + rays", build_s + query_s,
             embree_mb, walls.size(), median(walls));
  fmt::print("    Embree build {:.3f} s, 256 rays {:.6f} s; Embree's own allocations peak {:.1f} MB\n",
             build_s, query_s, static_cast<double>(embree_peak.load()) / (1024.0 * 1024.0));
  fmt::print("  ratio (ours / Embree, total time): {:.2f}\n", ours_s / (build_s + query_s));
  return 0;
}
