#include "poreshell/shell.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>

#include "poreshell/error.hpp"
#include "poreshell/isosurface.hpp"

namespace poreshell {
namespace {

constexpr int kLeafBlock = 8;        // side of the blocks whose points are tested one by one
constexpr int kTopBlock = 64;        // side of the blocks the scan starts from (one task each)
constexpr double kReachCells = 2.0;  // samples beyond the slab, so every crossing cell is complete

// Calls leaf(c) for the grid points c of the block [origin, origin + size)^3 that may lie within
// `reach` of the surface (by the unsigned distance, which is 1-Lipschitz: whole blocks are skipped on
// one query), in key order per leaf block; leaf makes the exact test and returns the unsigned distance
// it found, which skips the next points of the row that are as surely out of reach.
template <class Leaf>
void scan_block(const Surface& surface, const Grid& grid, const Coord& origin, int size, double reach,
                const Leaf& leaf) {
  const auto& d = grid.dims();
  if (origin.i >= d[0] || origin.j >= d[1] || origin.k >= d[2]) return;
  const double h = grid.h();
  const Vec3 center = grid.position(origin) + Vec3::Constant(0.5 * (size - 1) * h);
  if (std::abs(surface.distance(center)) > reach + 0.5 * std::sqrt(3.0) * (size - 1) * h) return;
  if (size > kLeafBlock) {
    const int half = size / 2;
    for (int c = 0; c < 8; ++c)
      scan_block(surface, grid,
                 {origin.i + (c & 1) * half, origin.j + ((c >> 1) & 1) * half, origin.k + (c >> 2) * half},
                 half, reach, leaf);
    return;
  }
  for (int k = origin.k; k < std::min(origin.k + size, d[2]); ++k)
    for (int j = origin.j; j < std::min(origin.j + size, d[1]); ++j)
      for (int i = origin.i; i < std::min(origin.i + size, d[0]); ++i) {
        const double distance = leaf(Coord{i, j, k});
        if (distance > reach) i += static_cast<int>(std::floor((distance - reach) / h));
      }
}

struct Sample {
  Coord point;
  double wall, pattern;
  bool incomplete;
};

}  // namespace

WallOffset parse_wall_offset(const std::string& name) {
  if (name == "centered") return WallOffset::centered;
  if (name == "inside") return WallOffset::inside;
  if (name == "outside") return WallOffset::outside;
  throw InputError("unknown --offset '" + name +
                   "': use centered (wall around the surface), inside or outside (wall on that side)");
}

std::string to_string(WallOffset offset) {
  switch (offset) {
    case WallOffset::inside:
      return "inside";
    case WallOffset::outside:
      return "outside";
    default:
      return "centered";
  }
}

double interpolate_band(const NarrowBand& band, std::span<const double> phi, const Vec3& p, bool* complete) {
  const PointStencil s = interpolation_stencil(band, p);
  if (complete != nullptr) *complete = s.complete;
  return s.present_weight > 0.0 ? s.interpolate(phi) : -1.0;
}

ShellSamples sample_shell(const Surface& surface, const NarrowBand& band, std::span<const double> phi,
                          const ShellOptions& options) {
  const double t = options.thickness;
  if (!(t > 0.0) || !std::isfinite(t)) throw InputError("the wall thickness must be a positive length");
  if (!(options.pattern_length > 0.0)) throw std::invalid_argument("shell: pattern_length must be > 0");
  if (phi.size() < band.size()) throw std::invalid_argument("shell: one phi value per band voxel needed");
  const double h =
      options.spacing > 0.0 ? options.spacing : std::min(band.grid().h(), t / kMinCellsAcrossWall);
  const double center_offset = options.offset == WallOffset::inside    ? -0.5 * t
                               : options.offset == WallOffset::outside ? 0.5 * t
                                                                       : 0.0;
  const double reach = std::abs(center_offset) + 0.5 * t + kReachCells * h;  // in unsigned distance

  // A grid of spacing h around the surface's box, one spare cell beyond the reach on every side.
  const Box box = surface.bounds();
  const Vec3 margin = Vec3::Constant(reach + 2.0 * h);
  const Vec3 extent = box.max - box.min + 2.0 * margin;
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil(extent[a] / h) + 1.0;
    if (n > 1 << 20)
      throw InputError("the shell's grid would be too large: choose a larger voxel size or wall");
    dims[a] = static_cast<int>(n);
  }
  ShellSamples out;
  out.grid = Grid(box.min - margin, h, dims);
  out.pattern_length = options.pattern_length;

  const bool signed_needed = options.offset != WallOffset::centered;
  const bool exact = surface.closest_point_is_exact();
  // One test per grid point that also samples it, so that the query deciding whether the point is near
  // enough gives its closest point too. An exact closest point gives the unsigned distance (|x - cp|):
  // one query per sample. Otherwise (or with no closest point) the distance and closest_point_at, as
  // for any surface.
  const auto sample = [&](const Coord& c, std::vector<Sample>& samples) -> double {
    const Vec3 x = out.grid.position(c);
    std::optional<Vec3> cp;
    if (exact) cp = surface.closest_point(x);
    double d = 0.0;
    if (cp) {
      d = (x - *cp).norm();
      if (!(d <= reach)) return d;
      // Only the surface's own distance has the sign when no side test is given.
      if (signed_needed && !options.side) d = surface.distance(x);
    } else {
      d = surface.distance(x);
      if (!(std::abs(d) <= reach)) return std::abs(d);
      cp = closest_point_at(surface, x, h, ClosestPointRule::exact);
    }
    const Vec3 p = cp.value_or(x);
    if (signed_needed && options.side) d = std::copysign(std::abs(d), options.side(x, p));
    bool complete = true;
    const double pattern = interpolate_band(band, phi, p, &complete);
    samples.push_back({c, std::abs(d - center_offset) - 0.5 * t, pattern, !complete});
    return 0.0;  // within reach
  };

  const std::array<int, 3> tops{(dims[0] + kTopBlock - 1) / kTopBlock, (dims[1] + kTopBlock - 1) / kTopBlock,
                                (dims[2] + kTopBlock - 1) / kTopBlock};
  const std::size_t top_count = std::size_t(tops[0]) * std::size_t(tops[1]) * std::size_t(tops[2]);
  std::vector<std::vector<Sample>> per_block(top_count);
  tbb::parallel_for(std::size_t{0}, top_count, [&](std::size_t b) {
    const Coord origin{static_cast<int>(b % std::size_t(tops[0])) * kTopBlock,
                       static_cast<int>((b / std::size_t(tops[0])) % std::size_t(tops[1])) * kTopBlock,
                       static_cast<int>(b / (std::size_t(tops[0]) * std::size_t(tops[1]))) * kTopBlock};
    std::vector<Sample>& samples = per_block[b];
    scan_block(surface, out.grid, origin, kTopBlock, reach,
               [&](const Coord& c) { return sample(c, samples); });
  });
  // In key order, whatever the blocks: the isosurface then needs no sorted copy of its own (two
  // extractions read these samples), and the order does not depend on the scan's blocking.
  std::size_t total = 0;
  for (const auto& block : per_block) total += block.size();
  std::vector<Sample> all;
  all.reserve(total);
  for (auto& block : per_block) {
    all.insert(all.end(), block.begin(), block.end());
    block = {};
  }
  tbb::parallel_sort(all.begin(), all.end(), [&](const Sample& a, const Sample& b) {
    return out.grid.key(a.point) < out.grid.key(b.point);
  });
  out.points.resize(total);
  out.wall.resize(total);
  out.pattern.resize(total);
  tbb::parallel_for(std::size_t{0}, total, [&](std::size_t n) {
    out.points[n] = all[n].point;
    out.wall[n] = all[n].wall;
    out.pattern[n] = all[n].pattern;
  });
  for (const Sample& s : all) out.incomplete_stencils += s.incomplete;
  return out;
}

TriangleMesh shell_mesh(const ShellSamples& samples, double iso) {
  std::vector<double> values(samples.points.size());
  tbb::parallel_for(std::size_t{0}, values.size(), [&](std::size_t n) {
    values[n] = std::max(samples.wall[n], samples.pattern_length * (samples.pattern[n] - iso));
  });
  const SparseField field{&samples.grid, samples.points, values, samples.grid.h()};
  return extract_isosurface(field, 0.0);
}

TriangleMesh unperforated_shell_mesh(const ShellSamples& samples) {
  const SparseField field{&samples.grid, samples.points, samples.wall, samples.grid.h()};
  return extract_isosurface(field, 0.0);
}

}  // namespace poreshell
