#include "shell/shell.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "band/band_scan.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "geometry/isosurface.hpp"
#include "shell/trim_line.hpp"

namespace poreshell {
namespace {

constexpr int kTopBlock = 64;  // side of the blocks the scan starts from (one task each)
// Samples beyond the slab, so that every cube with a corner inside has all 8: a cube's corners lie
// within its diagonal, sqrt(3) cells, of each other and the distance is 1-Lipschitz (a little more
// than sqrt(3) against rounding).
constexpr double kReachCells = 1.7325;
// The shell grid's extent beyond the slab: the reach and spare cells, and a quarter cell more so that the
// wall's faces and the box's planes fall between grid planes where the surface touches its box (see
// sample_shell).
constexpr double kMarginCells = 4.25;

// Beyond the trim line's reach: no trim (a part of the wall that is always inside).
constexpr double kNoTrim = -1e30;

struct Sample {
  Coord point;
  double slab, trim, pattern;
  bool incomplete;
};

}  // namespace

std::string to_string(WallOffset offset) {
  return std::string(name_of(offset));
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

  // A grid of spacing h around the surface's box, spare cells beyond the reach on every side. Where the
  // surface touches its box (a flat sheet's plane, a sphere's pole, a sleeve's cut end), the wall's faces
  // lie at box.min - |c| - t/2 plus multiples of t, and a trim line's end face at box.min itself. On a
  // grid plane F is 0 at grid points (a point on the surface counts as outside): a face there has no
  // crossing inside any edge, only clamped ones kSnap = 0.05 of an edge off it, which moved such a face
  // by 0.05 h (a 2 mm wall at h = t/3 measured 1.933 mm on a flat sheet, before clamped crossings were
  // moved back onto the surface, edge_crossings.hpp; not measured since), and where an end face meets the
  // wall's faces no crease point can be made (isosurface.hpp), so that edge stays chamfered (up to 0.4 mm
  // on a 2.5 mm sleeve whose ends lay on grid planes with half a cell here). A quarter cell puts the faces a
  // quarter cell from the grid planes, and the box's own planes, |c| + t/2 = 1.5 h or 3 h further at h = t/3
  // (the refined spacing), a quarter or three quarters: all cross their edges well inside the clamp. (On the
  // band's grid, used as it is, that holds only by chance.)
  const Box box = surface.bounds();
  const Vec3 margin = Vec3::Constant(std::abs(center_offset) + 0.5 * t + kMarginCells * h);
  const bool exact = surface.closest_point_is_exact();
  // On the band's own grid points where the spacing is the band's: there a sample that is a band voxel
  // takes the band's exact closest point instead of a surface query (about half the samples when the
  // wall is about as thick as the band; the queries were most of the sampling's time).
  const Grid& band_grid = band.grid();
  const bool on_band_grid = exact && h == band_grid.h();
  Vec3 grid_origin = box.min - margin;
  Coord to_band{0, 0, 0};
  if (on_band_grid) {
    const Vec3 cells = ((grid_origin - band_grid.origin()) / h).array().floor();
    grid_origin = band_grid.origin() + h * cells;
    to_band = {static_cast<int>(cells.x()), static_cast<int>(cells.y()), static_cast<int>(cells.z())};
  }
  const Vec3 extent = box.max + margin - grid_origin;
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil(extent[a] / h) + 1.0;
    if (n > 1 << 20)
      throw OptionError("wall",
                        "the shell's grid would be too large for this `wall`: ask for a wall well below "
                        "the model's size, or a larger `voxel_size`");
    dims[a] = static_cast<int>(n);
  }
  ShellSamples out;
  out.grid = Grid(grid_origin, h, dims);
  out.pattern_length = options.pattern_length;

  // The open boundary's trim line, asked as far from it as a sample within reach of the surface can
  // matter: points farther from the boundary are beyond reach, or far behind the trim line.
  std::optional<TrimLine> trim;
  if (options.open_mesh != nullptr) {
    trim.emplace(*options.open_mesh, reach + 2.0 * h);
    if (trim->empty()) trim.reset();
  }

  const bool signed_needed = options.offset != WallOffset::centered;
  // One test per grid point that also samples it, so that the query deciding whether the point is near
  // enough gives its closest point too. An exact closest point gives the unsigned distance (|x - cp|):
  // one query per sample. Otherwise (or with no closest point) the distance and closest_point_at, as
  // for any surface.
  const auto sample = [&](const Coord& c, std::vector<Sample>& samples) -> double {
    const Vec3 x = out.grid.position(c);
    std::optional<Vec3> cp;
    if (on_band_grid) {
      const std::int64_t v = band.find({c.i + to_band.i, c.j + to_band.j, c.k + to_band.k});
      if (v >= 0) cp = band.closest_point(static_cast<std::size_t>(v));
    }
    if (exact && !cp) cp = surface.closest_point(x);
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
    double beyond_trim = kNoTrim;
    if (trim) beyond_trim = trim->beyond(x).value_or(kNoTrim);
    // Past the trim line the closest point is on the boundary, and |x - cp| would round the slab into a
    // cap around it. Its part across the line, the distance to the surface's tangent plane there, goes
    // on as the slab does behind it, so the crease where the end face meets the wall's faces is where
    // both parts' values say (the isosurface's crease points).
    if (beyond_trim > 0.0) d = std::copysign(std::sqrt(std::max(0.0, d * d - beyond_trim * beyond_trim)), d);
    const double slab = std::abs(d - center_offset) - 0.5 * t;
    samples.push_back({c, slab, beyond_trim, pattern, !complete});
    return 0.0;  // within reach
  };

  const std::array<int, 3> tops{(dims[0] + kTopBlock - 1) / kTopBlock, (dims[1] + kTopBlock - 1) / kTopBlock,
                                (dims[2] + kTopBlock - 1) / kTopBlock};
  const std::size_t top_count = std::size_t(tops[0]) * std::size_t(tops[1]) * std::size_t(tops[2]);
  std::vector<std::vector<Sample>> per_block(top_count);
  monitored_for(top_count, options.progress.part(0.0, 0.9), [&](std::size_t b) {
    const Coord origin{static_cast<int>(b % std::size_t(tops[0])) * kTopBlock,
                       static_cast<int>((b / std::size_t(tops[0])) % std::size_t(tops[1])) * kTopBlock,
                       static_cast<int>(b / (std::size_t(tops[0]) * std::size_t(tops[1]))) * kTopBlock};
    std::vector<Sample>& samples = per_block[b];
    for_each_point_near(surface, out.grid, origin, kTopBlock, reach,
                        [&](const Coord& c) { return sample(c, samples); });
    std::sort(samples.begin(), samples.end(), [&](const Sample& p, const Sample& q) {
      return out.grid.key(p.point) < out.grid.key(q.point);
    });
  });
  // Written in key order, so the isosurface needs no sorted copy of its own (two extractions read these
  // samples). Key order within a layer of top blocks is plane by plane, row by row, and each row is
  // the same row of the blocks along x in turn: a merge without a copy of all samples.
  std::vector<std::size_t> layer_first(static_cast<std::size_t>(tops[2]) + 1, 0);
  for (std::size_t b = 0; b < top_count; ++b)
    layer_first[b / (std::size_t(tops[0]) * std::size_t(tops[1])) + 1] += per_block[b].size();
  for (std::size_t l = 0; l < static_cast<std::size_t>(tops[2]); ++l) layer_first[l + 1] += layer_first[l];
  const std::size_t total = layer_first.back();
  out.points.resize(total);
  out.wall.resize(total);
  out.pattern.resize(total);
  if (trim) {
    out.slab.resize(total);
    out.trim.resize(total);
  }
  std::vector<std::int64_t> incomplete(static_cast<std::size_t>(tops[2]), 0);
  monitored_for(static_cast<std::size_t>(tops[2]), options.progress.part(0.9, 1.0), [&](std::size_t l) {
    const std::size_t blocks_in_layer = std::size_t(tops[0]) * std::size_t(tops[1]);
    std::vector<std::size_t> cursor(blocks_in_layer, 0);
    std::size_t n = layer_first[l];
    const int k_end = std::min(static_cast<int>(l + 1) * kTopBlock, dims[2]);
    for (int k = static_cast<int>(l) * kTopBlock; k < k_end; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (std::size_t bi = 0; bi < std::size_t(tops[0]); ++bi) {
          const std::size_t in_layer = bi + std::size_t(tops[0]) * std::size_t(j / kTopBlock);
          const std::vector<Sample>& block = per_block[l * blocks_in_layer + in_layer];
          for (std::size_t& c = cursor[in_layer];
               c < block.size() && block[c].point.k == k && block[c].point.j == j; ++c, ++n) {
            out.points[n] = block[c].point;
            out.wall[n] = std::max(block[c].slab, block[c].trim);
            out.pattern[n] = block[c].pattern;
            if (trim) {
              out.slab[n] = block[c].slab;
              out.trim[n] = block[c].trim;
            }
            incomplete[l] += block[c].incomplete;
          }
        }
    for (std::size_t b = 0; b < blocks_in_layer; ++b) per_block[l * blocks_in_layer + b] = {};
  });
  for (std::int64_t count : incomplete) out.incomplete_stencils += count;
  return out;
}

TriangleMesh shell_mesh(const ShellSamples& samples, double iso, const StageProgress& progress,
                        bool sharp_creases) {
  std::vector<double> pores(samples.points.size()), values(samples.points.size());
  tbb::parallel_for(std::size_t{0}, values.size(), [&](std::size_t n) {
    pores[n] = samples.pattern_length * (samples.pattern[n] - iso);
    values[n] = std::max(samples.wall[n], pores[n]);
  });
  progress.check();
  // The pores' walls meet the wall's faces, and those the end faces at the trim line, at sharp edges:
  // meshed from the parts (isosurface.hpp).
  std::vector<std::span<const double>> parts{samples.wall, pores};
  SparseField field{&samples.grid, samples.points, values, samples.grid.h()};
  if (!samples.trim.empty()) parts = {samples.slab, samples.trim, pores};
  field.parts = parts;
  field.sharp_creases = sharp_creases;
  return extract_isosurface(field, 0.0, progress);
}

TriangleMesh unperforated_shell_mesh(const ShellSamples& samples) {
  const SparseField field{&samples.grid, samples.points, samples.wall, samples.grid.h()};
  return extract_isosurface(field, 0.0);
}

std::int64_t unperforated_shell_euler(const ShellSamples& samples, const StageProgress& progress) {
  const SparseField field{&samples.grid, samples.points, samples.wall, samples.grid.h()};
  return isosurface_euler_characteristic(field, 0.0, progress);
}

SolidWallPoints solid_wall_points(const ShellSamples& samples) {
  SolidWallPoints out;
  out.grid = samples.grid;
  out.keys.reserve(static_cast<std::size_t>(
      std::count_if(samples.wall.begin(), samples.wall.end(), [](double w) { return w < 0.0; })));
  for (std::size_t i = 0; i < samples.points.size(); ++i)
    if (samples.wall[i] < 0.0) out.keys.push_back(samples.grid.key(samples.points[i]));
  return out;
}

std::int64_t wall_voids_euler(PartsSummary& parts, const SolidWallPoints& wall,
                              const std::function<Vec3(const Vec3&)>& to_grid) {
  std::int64_t euler = 0;
  for (const PartsSummary::Void& v : parts.voids)
    if (!wall.contains(to_grid(v.inside))) {
      euler += v.euler_characteristic;
      ++parts.removed_wall_voids;
    }
  return euler;
}

bool SolidWallPoints::contains(const Vec3& p) const {
  const Vec3 q = grid.to_index_space(p);
  const Coord c{static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())),
                static_cast<int>(std::lround(q.z()))};
  return grid.contains(c) && std::binary_search(keys.begin(), keys.end(), grid.key(c));
}

}  // namespace poreshell
