#include "band/band.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <span>

#include "band/band_scan.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"

namespace poreshell {
namespace {

int parity(const Coord& c) {
  return (c.i + c.j + c.k) & 1;
}

// psi and its central-difference gradient grad_h psi at a grid point (section 2).
struct LevelSetSample {
  double psi;
  Vec3 gradient;
};

LevelSetSample sample_level_set(const Surface& surface, const Vec3& x, double h) {
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    Vec3 e = Vec3::Zero();
    e[a] = h;
    g[a] = (surface.distance(x + e) - surface.distance(x - e)) / (2.0 * h);
  }
  return {surface.distance(x), g};
}

bool in_band(const LevelSetSample& s, double delta) {
  return std::abs(s.psi) < delta * s.gradient.norm();
}

// A band voxel found by the scan, with its psi (kept: the band stores it).
struct ScannedVoxel {
  std::int64_t key;
  double psi;
};

// The voxels with |psi| < within that satisfy the band rule, by key. Only points with |psi| <
// gradient_bound delta can (|grad_h psi| <= sqrt(3) for a 1-Lipschitz psi); the neighbours of those
// within are within the near field's reach. Points within h of the surface are band voxels whatever
// their discrete gradient, which vanishes across a thin part's middle (the bunny's ears: 112 of them,
// which the closure added back before): they carry the surface's area, and a surface layer of them
// then holds exactly the band's (BandOptions::surface_layer).
std::vector<ScannedVoxel> band_voxels(const NearField& near, const Surface& surface, const Grid& grid,
                                      double delta, double within, const StageProgress& progress) {
  const double inv_2h = 0.5 / grid.h();
  const auto psi_at = [&](const Coord& c) {
    const double psi = near.psi(c);
    return std::isnan(psi) ? surface.distance(grid.position(c)) : psi;  // beyond reach: only by rounding
  };
  std::vector<std::vector<ScannedVoxel>> per_row(near.row_count());
  monitored_for(near.row_count(), progress, [&](std::size_t r) {
    near.for_each_near_point(r, [&](const Coord& c, double psi) {
      if (std::abs(psi) >= within) return;
      if (std::abs(psi) < grid.h()) {
        per_row[r].push_back({grid.key(c), psi});
        return;
      }
      const Vec3 gradient((psi_at({c.i + 1, c.j, c.k}) - psi_at({c.i - 1, c.j, c.k})) * inv_2h,
                          (psi_at({c.i, c.j + 1, c.k}) - psi_at({c.i, c.j - 1, c.k})) * inv_2h,
                          (psi_at({c.i, c.j, c.k + 1}) - psi_at({c.i, c.j, c.k - 1})) * inv_2h);
      if (in_band({psi, gradient}, delta)) per_row[r].push_back({grid.key(c), psi});
    });
  });
  std::vector<ScannedVoxel> found;
  for (auto& row : per_row) {
    found.insert(found.end(), row.begin(), row.end());
    row = {};
  }
  std::sort(found.begin(), found.end(),
            [](const ScannedVoxel& a, const ScannedVoxel& b) { return a.key < b.key; });
  return found;
}

// The closest point of grid point c by the band's rule: the near field's where it recorded the surface's
// exact one, else asked again.
Vec3 closest_point_of(const NearField& near, const Surface& surface, const Grid& grid, const Coord& c,
                      ClosestPointRule rule) {
  if (rule == ClosestPointRule::exact && near.has_closest_points()) {
    const Vec3 cp = near.closest_point(c);
    if (!std::isnan(cp.x())) return cp;
  }
  return closest_point_at(surface, grid, c, rule);
}

// Voxels per task in the passes over all band voxels below.
constexpr std::size_t kVoxelGrain = 1 << 14;

// Key differences to the 6 neighbours, in kFaceOffsets' order.
std::array<std::int64_t, NarrowBand::kNeighbors> neighbour_key_deltas(const Grid& grid) {
  const std::int64_t nx = grid.dims()[0], nxy = nx * grid.dims()[1];
  return {-1, 1, -nx, nx, -nxy, nxy};
}

// For each voxel v (sorted keys) and neighbour direction o: the band index of key_v + delta_o, or -1.
// The shifted keys are sorted too, so each task walks the key array forward once per direction instead
// of a binary search per neighbour (36 M serial searches at 6 M voxels were a third of the band's
// build). Band voxels keep off the grid's edge (checked first), so key +- 1 is the x-neighbour.
void band_neighbours(std::span<const std::int64_t> keys, const Grid& grid, std::vector<std::int32_t>& table) {
  const auto deltas = neighbour_key_deltas(grid);
  table = std::vector<std::int32_t>(keys.size() * NarrowBand::kNeighbors);  // exact size: kept by the band
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size(), kVoxelGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (int o = 0; o < NarrowBand::kNeighbors; ++o) {
                        const std::int64_t d = deltas[static_cast<std::size_t>(o)];
                        auto at = std::lower_bound(keys.begin(), keys.end(), keys[r.begin()] + d);
                        for (std::size_t v = r.begin(); v != r.end(); ++v) {
                          const std::int64_t target = keys[v] + d;
                          while (at != keys.end() && *at < target) ++at;
                          table[v * NarrowBand::kNeighbors + static_cast<std::size_t>(o)] =
                              at != keys.end() && *at == target ? static_cast<std::int32_t>(at - keys.begin())
                                                                : -1;
                        }
                      }
                    });
}

// The keys of the grid points next to the band that are not band voxels (the ghosts), ascending.
std::vector<std::int64_t> ghost_keys_of(std::span<const std::int64_t> keys, const Grid& grid,
                                        std::span<const std::int32_t> table) {
  const auto deltas = neighbour_key_deltas(grid);
  const std::size_t tasks = (keys.size() + kVoxelGrain - 1) / kVoxelGrain;
  std::vector<std::vector<std::int64_t>> per_task(tasks);
  tbb::parallel_for(std::size_t{0}, tasks, [&](std::size_t t) {
    const std::size_t end = std::min(keys.size(), (t + 1) * kVoxelGrain);
    for (std::size_t v = t * kVoxelGrain; v < end; ++v)
      for (std::size_t o = 0; o < NarrowBand::kNeighbors; ++o)
        if (table[v * NarrowBand::kNeighbors + o] < 0) per_task[t].push_back(keys[v] + deltas[o]);
    std::sort(per_task[t].begin(), per_task[t].end());
  });
  std::vector<std::int64_t> ghosts;
  for (auto& part : per_task) {
    ghosts.insert(ghosts.end(), part.begin(), part.end());
    part = {};
  }
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  return ghosts;
}

}  // namespace

std::optional<Vec3> closest_point_at(const Surface& surface, const Vec3& x, double h, ClosestPointRule rule) {
  if (rule == ClosestPointRule::exact)
    if (auto cp = surface.closest_point(x)) return cp;
  const LevelSetSample s = sample_level_set(surface, x, h);
  const double g2 = s.gradient.squaredNorm();
  if (!(g2 > 0.0)) return std::nullopt;
  return Vec3(x - s.gradient * (s.psi / g2));
}

Vec3 closest_point_at(const Surface& surface, const Grid& grid, const Coord& c, ClosestPointRule rule) {
  const std::optional<Vec3> cp = closest_point_at(surface, grid.position(c), grid.h(), rule);
  if (!cp) throw InputError("the distance function has no gradient at a band or ghost point");
  return *cp;
}

PointStencil interpolation_stencil(const NarrowBand& band, const Vec3& p) {
  const auto [base, t] = lattice_cell(band.grid().to_index_space(p));
  PointStencil s;
  std::array<std::int64_t, 2> pair{};
  for (int c = 0; c < 8; ++c) {
    const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
    const double w = trilinear_weight(t, c);
    if (di == 0) pair = band.find_x_pair({base.i, base.j + dj, base.k + dk});
    const std::int64_t idx = pair[static_cast<std::size_t>(di)];
    if (idx < 0) {
      s.complete = s.complete && w == 0.0;
      continue;
    }
    s.corner[c] = static_cast<std::int32_t>(idx);
    s.weight[c] = w;
    s.present_weight += w;
  }
  if (s.present_weight > 0.0)
    for (double& w : s.weight) w /= s.present_weight;
  return s;
}

std::array<std::int64_t, 2> NarrowBand::find_x_pair(const Coord& c) const {
  std::array<std::int64_t, 2> out{-1, -1};
  const Coord next{c.i + 1, c.j, c.k};
  if (!grid_.contains(c)) {
    if (grid_.contains(next)) out[1] = find(next);
    return out;
  }
  const std::int64_t key = grid_.key(c);
  auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  if (it != keys_.end() && *it == key) out[0] = it++ - keys_.begin();
  // key + 1 is the +x neighbour only inside the grid (else it is the next row's first point).
  if (grid_.contains(next) && it != keys_.end() && *it == key + 1) out[1] = it - keys_.begin();
  return out;
}

std::int64_t NarrowBand::find(const Coord& c) const {
  if (!grid_.contains(c)) return -1;
  const std::int64_t key = grid_.key(c);
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  return (it != keys_.end() && *it == key) ? it - keys_.begin() : -1;
}

namespace {

// Small bands (coarse multigrid levels) run as one task rather than paying the scheduler per ghost.
constexpr std::size_t kGhostGrain = 1024;

template <class T>
void fill_ghost_range(const std::vector<GhostStencil>& stencils, std::size_t n, std::size_t begin,
                      std::size_t end, std::span<T> extended) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, kGhostGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t g = r.begin(); g != r.end(); ++g)
                        extended[n + g] = stencils[g].interpolate(extended.data());
                    });
}

}  // namespace

// Each parity is split among the threads on its own: a thread then writes the ghosts around the band
// voxels it will likely read them from (both follow key order). One split over both halves gave one
// thread all the odd ghosts, and the other core's reads of them made the reference 1.6x slower on 2
// threads than the same fill split per parity.
void NarrowBand::fill_ghosts(std::span<double> extended) const {
  fill_ghosts(extended, 0);
  fill_ghosts(extended, 1);
}

void NarrowBand::fill_ghosts(std::span<float> extended) const {
  fill_ghosts(extended, 0);
  fill_ghosts(extended, 1);
}

void NarrowBand::fill_ghosts(std::span<double> extended, int parity) const {
  const auto [begin, end] = ghosts_of_parity(parity);
  fill_ghost_range(stencils_, voxels_.size(), begin, end, extended);
}

void NarrowBand::fill_ghosts(std::span<float> extended, int parity) const {
  const auto [begin, end] = ghosts_of_parity(parity);
  fill_ghost_range(stencils_, voxels_.size(), begin, end, extended);
}

std::vector<Vec3> NarrowBand::closest_points() const {
  std::vector<Vec3> cps(voxels_.size());
  for (std::size_t v = 0; v < cps.size(); ++v) cps[v] = closest_point(v);
  return cps;
}

std::size_t NarrowBand::memory_bytes() const {
  return voxels_.capacity() * sizeof(Coord) + keys_.capacity() * sizeof(std::int64_t) +
         distance_.capacity() * sizeof(double) + ghosts_.capacity() * sizeof(Coord) +
         neighbors_.capacity() * sizeof(std::int32_t) + stencils_.capacity() * sizeof(GhostStencil) +
         closest_point_offsets_.capacity() * sizeof(closest_point_offsets_[0]);
}

Grid covering_grid(const Surface& surface, double h) {
  constexpr int kPadCells = 6;  // the band (1.9 cells), its ghosts and a margin
  const Box box = surface.bounds();
  const Vec3 origin = box.min - Vec3::Constant(kPadCells * h);
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a)
    dims[a] = static_cast<int>(std::ceil((box.max[a] - box.min[a]) / h)) + 2 * kPadCells + 1;
  return Grid(origin, h, dims);
}

// Hand-written rather than OpenVDB's meshToVolume (Debian's libopenvdb-dev), which was timed on the
// bunny (unsigned, renormalisation off, +-4.5 voxels, closest-polygon index grid): 0.64-0.68 s at N = 131
// against 0.8 s for this whole stage, and 5.8-7.5 s at N = 830 against 20-27 s (docs/benchmarks.md,
// search "meshToVolume"). No gain at the paper's grid, so no dependency; the lever for large grids.
// build_band's steps, each writing the band's own arrays.
class BandBuilder {
 public:
  BandBuilder(NarrowBand& band, const NearField& near, const Surface& surface, const BandOptions& options)
      : band_(band), near_(near), surface_(surface), grid_(band.grid_), options_(options) {}

  // The voxels of `keys` (ascending) and their neighbour table; none on the grid's edge.
  void take_voxels(const std::vector<std::int64_t>& keys) {
    band_.keys_ = keys;
    band_.voxels_.resize(keys.size());
    for (std::size_t v = 0; v < keys.size(); ++v) band_.voxels_[v] = grid_.coord(keys[v]);
    const auto& d = grid_.dims();
    if (std::any_of(band_.voxels_.begin(), band_.voxels_.end(), [&](const Coord& c) {
          return c.i <= 0 || c.j <= 0 || c.k <= 0 || c.i >= d[0] - 1 || c.j >= d[1] - 1 || c.k >= d[2] - 1;
        }))
      throw InputError("the narrow band touches the edge of the grid: enlarge the domain or add padding");
    band_neighbours(band_.keys_, grid_, band_.neighbors_);
  }

  // Closure: every corner of every ghost's interpolation cell must be a band voxel. Corners are within
  // sqrt(3) h of the surface, so for a true distance function the rule already holds; add the rare
  // exceptions (curved level sets with |grad_h psi| < 1) and rebuild the ghosts.
  void close_ghost_stencils(std::vector<std::int64_t>& keys, const StageProgress& progress) {
    for (int round = 0;; ++round) {
      const StageProgress round_progress = progress.part(0.6 + 0.02 * round, 0.8 + 0.02 * round);
      round_progress.check();
      take_voxels(keys);
      round_progress.advance(0.2);
      const std::vector<std::int64_t> added = stencil_corners_missing(round_progress);
      if (added.empty()) return;
      if (round == 8) throw std::runtime_error("narrow band closure did not settle after 8 rounds");
      band_.stats_.closure_added += static_cast<std::int64_t>(added.size());
      keys.insert(keys.end(), added.begin(), added.end());
      std::sort(keys.begin(), keys.end());
    }
  }

  // The neighbour table's ghost entries (band indices from the last round; ghosts by their parity's key
  // order), and the paper's ghost count.
  void link_ghosts() {
    const auto n = static_cast<std::int64_t>(band_.voxels_.size());
    tbb::parallel_for(std::size_t{0}, band_.voxels_.size(), [&](std::size_t v) {
      for (int o = 0; o < NarrowBand::kNeighbors; ++o) {
        std::int32_t& idx = band_.neighbors_[v * NarrowBand::kNeighbors + static_cast<std::size_t>(o)];
        if (idx >= 0) continue;
        const Coord nb = shifted(band_.voxels_[v], kFaceOffsets[static_cast<std::size_t>(o)]);
        const auto [begin, end] = band_.ghosts_of_parity(parity(nb));
        const auto first = band_.ghosts_.begin() + static_cast<std::ptrdiff_t>(begin);
        const auto it =
            std::lower_bound(first, band_.ghosts_.begin() + static_cast<std::ptrdiff_t>(end), grid_.key(nb),
                             [&](const Coord& a, std::int64_t b) { return grid_.key(a) < b; });
        idx = static_cast<std::int32_t>(n + (it - band_.ghosts_.begin()));
      }
    });
    // The paper's ghost set is { I |grad_h I| != 0 }: ghosts with an unbalanced band neighbour pair. A
    // ghost's band neighbours are the voxels whose neighbour entries point at it (direction o from the
    // voxel is o ^ 1 from the ghost): one pass over the table, not 6 searches per ghost.
    std::vector<std::uint8_t> band_sides(band_.ghosts_.size(), 0);  // bit o: the neighbour in direction o
    for (std::size_t e = 0; e < band_.neighbors_.size(); ++e)
      if (band_.neighbors_[e] >= n)
        band_sides[static_cast<std::size_t>(band_.neighbors_[e] - n)] |=
            static_cast<std::uint8_t>(1u << ((e % NarrowBand::kNeighbors) ^ 1));
    band_.stats_.paper_ghosts = std::count_if(band_sides.begin(), band_sides.end(), [](std::uint8_t sides) {
      return ((sides ^ (sides >> 1)) & 0b010101) != 0;  // -a and +a differ for some axis a
    });
  }

  // Each voxel's distance (the scan's, else the near field's) and closest point.
  void fill_distances(const std::vector<ScannedVoxel>& scanned, const StageProgress& progress) {
    band_.distance_.resize(band_.voxels_.size());
    band_.closest_point_offsets_.resize(band_.voxels_.size());
    monitored_for(band_.voxels_.size(), progress, [&](std::size_t v) {
      const std::int64_t key = band_.keys_[v];
      const auto it = std::lower_bound(scanned.begin(), scanned.end(), key,
                                       [](const ScannedVoxel& a, std::int64_t k) { return a.key < k; });
      // Voxels added by the closure were not scanned into the band: the near field has them.
      if (it != scanned.end() && it->key == key) {
        band_.distance_[v] = it->psi;
      } else {
        const double psi = near_.psi(band_.voxels_[v]);
        band_.distance_[v] = std::isnan(psi) ? surface_.distance(grid_.position(band_.voxels_[v])) : psi;
      }
      const Vec3 offset =
          (closest_point_of(near_, surface_, grid_, band_.voxels_[v], options_.closest_point) -
           grid_.position(band_.voxels_[v])) /
          grid_.h();
      band_.closest_point_offsets_[v] = {static_cast<float>(offset.x()), static_cast<float>(offset.y()),
                                         static_cast<float>(offset.z())};
    });
  }

 private:
  // The ghosts of the current voxels, their stencils at their closest points, and the stencil corners
  // that are not band voxels (sorted, once each).
  std::vector<std::int64_t> stencil_corners_missing(const StageProgress& round_progress) {
    std::vector<std::int64_t> ghost_keys = ghost_keys_of(band_.keys_, grid_, band_.neighbors_);
    round_progress.advance(0.3);
    const auto even = std::stable_partition(ghost_keys.begin(), ghost_keys.end(),
                                            [&](std::int64_t key) { return parity(grid_.coord(key)) == 0; });
    band_.odd_ghosts_begin_ = static_cast<std::size_t>(even - ghost_keys.begin());
    band_.ghosts_.resize(ghost_keys.size());
    for (std::size_t g = 0; g < ghost_keys.size(); ++g) band_.ghosts_[g] = grid_.coord(ghost_keys[g]);

    band_.stencils_.assign(ghost_keys.size(), {});
    std::vector<std::vector<std::int64_t>> missing(ghost_keys.size());
    std::vector<double> offsets(ghost_keys.size(), 0.0);
    monitored_for(ghost_keys.size(), round_progress.part(0.3, 1.0), [&](std::size_t g) {
      const Coord c = band_.ghosts_[g];
      const Vec3 cp = closest_point_of(near_, surface_, grid_, c, options_.closest_point);
      offsets[g] = (cp - grid_.position(c)).norm() / grid_.h();
      const auto [base, t] = lattice_cell(grid_.to_index_space(cp));
      GhostStencil& s = band_.stencils_[g];
      s.t = {static_cast<float>(t.x()), static_cast<float>(t.y()), static_cast<float>(t.z())};
      for (int r = 0; r < 4; ++r) {  // the cell's 4 rows along x: one search finds both corners
        const Coord row_start{base.i, base.j + (r & 1), base.k + (r >> 1)};
        const std::array<std::int64_t, 2> idx = band_.find_x_pair(row_start);
        s.row[static_cast<std::size_t>(r)] = static_cast<std::int32_t>(std::max<std::int64_t>(idx[0], 0));
        for (int x = 0; x < 2; ++x) {
          if (idx[static_cast<std::size_t>(x)] >= 0) continue;
          const Coord cc{row_start.i + x, row_start.j, row_start.k};
          if (!grid_.contains(cc)) throw InputError("a closest point lies outside the grid: add padding");
          missing[g].push_back(grid_.key(cc));
        }
      }
    });
    std::vector<std::int64_t> added;
    for (const auto& m : missing) added.insert(added.end(), m.begin(), m.end());
    if (added.empty())
      band_.stats_.max_closest_point_offset = *std::max_element(offsets.begin(), offsets.end());
    std::sort(added.begin(), added.end());
    added.erase(std::unique(added.begin(), added.end()), added.end());
    return added;
  }

  NarrowBand& band_;
  const NearField& near_;
  const Surface& surface_;
  const Grid& grid_;
  const BandOptions& options_;
};

NarrowBand build_band(const Surface& surface, const Grid& grid, const BandOptions& options) {
  NarrowBand band(grid);
  const double delta = options.delta_in_h * grid.h();
  // Reach: band candidates (|psi| < gradient_bound delta) and one cell beyond, which holds their
  // neighbours, the ghosts and the ghosts' stencil corners (within sqrt(3) h of the surface); 1% for
  // rounding. A surface layer needs only the points within h. Shares of the build's time (the bunny at 400
  // points): the near field, the band rule, the closure rounds (one, rarely more), the voxels' distances and
  // closest points.
  const StageProgress& progress = options.progress;
  const double bound = std::clamp(options.gradient_bound, 1.0, std::sqrt(3.0));
  const double within = options.surface_layer ? grid.h() : delta * bound;
  const NearField near(surface, grid, options.surface_layer ? 1.01 * within : within + 1.01 * grid.h(),
                       progress.part(0.0, 0.5));
  band.stats_.candidate_blocks = near.blocks_scanned();
  const std::vector<ScannedVoxel> scanned =
      band_voxels(near, surface, grid, delta, within, progress.part(0.5, 0.6));
  std::vector<std::int64_t> keys(scanned.size());
  for (std::size_t v = 0; v < scanned.size(); ++v) keys[v] = scanned[v].key;
  if (keys.empty())
    throw InputError(
        "the narrow band is empty: the surface does not cross the grid; check its size and position");
  if (keys.size() >= static_cast<std::size_t>(INT32_MAX / 2))
    throw InputError("the narrow band has too many voxels for 32-bit indices: use a coarser resolution");

  BandBuilder builder(band, near, surface, options);
  if (options.surface_layer) {
    band.surface_layer_ = true;
    builder.take_voxels(keys);
  } else {
    builder.close_ghost_stencils(keys, progress);
    progress.advance(0.8);
    builder.link_ghosts();
    progress.advance(0.85);
  }
  builder.fill_distances(scanned, progress.part(0.85, 1.0));
  return band;
}

}  // namespace poreshell
