#include "band/memory_estimate.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include "band/band.hpp"
#include "core/grid.hpp"

namespace poreshell {
namespace {

// MemAvailable from /proc/meminfo, else the physical memory.
double available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0.0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024.0;
  return static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
}

// What is left of the address space under RLIMIT_AS (ulimit -v), or infinity without one. A run
// estimated above it would only fail after minutes, with the mesh half built (issue 47).
double address_space_left_bytes() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY)
    return std::numeric_limits<double>::infinity();
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0;  // the address space in use now
  statm >> pages;
  return static_cast<double>(limit.rlim_cur) - pages * static_cast<double>(sysconf(_SC_PAGE_SIZE));
}

}  // namespace

double estimate_band_voxels(const Surface& surface, const Box& domain, int resolution) {
  const int coarse_points = (resolution - 1) / 8 + 1;
  if (coarse_points < 17) return 0.0;  // a small run: the estimate would be coarser than the run itself
  const double fine_h = (domain.max - domain.min).maxCoeff() / (resolution - 1);
  const double coarse_h = 8.0 * fine_h;
  Box padded{domain.min - Vec3::Constant(4 * coarse_h), domain.max + Vec3::Constant(4 * coarse_h)};
  const Grid coarse = Grid::fitted(
      padded, static_cast<int>(std::lround((padded.max - padded.min).maxCoeff() / coarse_h)) + 1);
  try {
    return static_cast<double>(build_band(surface, coarse).size()) * std::pow(coarse.h() / fine_h, 2);
  } catch (const std::exception&) {
    return 0.0;  // no estimate on this grid: the run itself will say what is wrong
  }
}

MemoryLimit memory_limit(double limit_gb) {
  if (limit_gb > 0.0) return {limit_gb * 1e9, "allowed by `max_memory_gb`"};
  const double available = available_memory_bytes(), address_space = address_space_left_bytes();
  if (address_space < available) return {address_space, "left under the address-space limit (ulimit -v)"};
  return {available, "available"};
}

}  // namespace poreshell
