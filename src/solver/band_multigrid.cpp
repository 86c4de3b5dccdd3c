#include "solver/band_multigrid.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/error.hpp"
#include "core/heap.hpp"
#include "core/parallel.hpp"
#include "geometry/point_tree.hpp"

namespace poreshell {
namespace {

// A level with z h^2 >= this is diagonally dominant enough for smoothing alone (Jacobi contraction <= 6/14).
constexpr double kCoarseEnough = 8.0;
constexpr std::size_t kSmallestBand = 1000;  // coarsest bands are smoothed to convergence: cheap
constexpr int kMaxLevels = 8;
constexpr int kSmoothingSweeps = 2;  // before and after the coarse correction
constexpr int kCoarsestSweeps = 10;  // between residual checks
constexpr int kMaxCoarsestSweeps = 400;
// Coarse bands thinner than the paper's 1.1 sqrt(3) H: the closure still puts every ghost's stencil in
// the band, a fifth fewer voxels and searches per level, and fewer V-cycles where the surface faces
// itself across a few coarse cells (bunny, 830 points: 126 -> 117 in the fine run; 131 points: 438 ->
// 440). At 1.2 H the closure did not settle on the bunny's sampled surface; 1.6 keeps a margin.
constexpr double kCoarseDeltaInH = 1.6;

// Coarse levels hold a few thousand voxels: one task each, not a scheduler round trip per loop.
constexpr std::size_t kGrain = 2048;

template <class Body>
void for_each_index(std::size_t n, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
                    });
}

// A finer level's closest points as the surface a coarse level is built on: distance and closest point
// by the nearest of them (a point tree), not by the surface's own search. The points (surface_samples)
// lie on the surface about h apart, so the next level (spacing 2h) sees the surface within about h / 2:
// enough for a preconditioner's coarse levels, and far cheaper than exact searches from points up to 9 h off
// a scan's many small triangles (those took 0.4 s of the bunny's 0.5 s of set-up at N = 131).
class SampledSurface final : public Surface {
 public:
  explicit SampledSurface(const std::vector<Vec3>& samples)
      : tree_(samples), bounds_{samples[0], samples[0]} {
    for (const Vec3& p : samples) {
      bounds_.min = bounds_.min.cwiseMin(p);
      bounds_.max = bounds_.max.cwiseMax(p);
    }
  }
  double distance(const Vec3& p) const override { return tree_.nearest(p).second; }
  std::optional<Vec3> closest_point(const Vec3& p) const override {
    return tree_.point(tree_.nearest(p).first);
  }
  bool closest_point_is_exact() const override { return true; }
  SurfaceQuery distance_and_closest_point(const Vec3& p) const override {
    const auto [i, d] = tree_.nearest(p);
    return {d, tree_.point(i)};
  }
  Box bounds() const override { return bounds_; }
  std::string name() const override { return "closest points of a finer level"; }

 private:
  PointTree tree_;
  Box bounds_;
};

// The closest points of the voxels within sqrt(3)/2 h of the surface: every cell the surface crosses has
// such a corner, so they cover the surface about h apart, with a third of the band's points (the
// others repeat them along the normals) and a third of the tree's memory.
std::vector<Vec3> surface_samples(const NarrowBand& band, std::span<const Vec3> cps) {
  const double near = 0.5 * std::sqrt(3.0) * band.grid().h();
  std::vector<Vec3> samples;
  for (std::size_t v = 0; v < band.size(); ++v)
    if (std::abs(band.distance()[v]) <= near) samples.push_back(cps[v]);
  return samples;
}

}  // namespace

BandInterpolation::BandInterpolation(const NarrowBand& from, std::span<const Vec3> points)
    : compact_(points.size()) {
  const Grid& grid = from.grid();
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
    const auto [base, t] = lattice_cell(grid.to_index_space(points[i]));
    Compact& s = compact_[i];
    for (int r = 0; r < 4; ++r) {
      const Coord c{base.i, base.j + (r & 1), base.k + (r >> 1)};
      const auto [at, next] = from.find_x_pair(c);
      if (at < 0 || next < 0) {
        s.row[0] = -1;  // marked: a partial stencil below
        return;
      }
      s.row[static_cast<std::size_t>(r)] = static_cast<std::int32_t>(at);
    }
    s.t = {static_cast<float>(t.x()), static_cast<float>(t.y()), static_cast<float>(t.z())};
  });
  for (std::size_t i = 0; i < points.size(); ++i) {  // rare: in order, so the numbering is deterministic
    if (compact_[i].row[0] >= 0) continue;
    const PointStencil point = interpolation_stencil(from, points[i]);
    if (!(point.present_weight > 1e-6))
      throw std::runtime_error("multigrid: a closest point has no band voxel around it");
    Partial p;
    p.corner = point.corner;
    for (int c = 0; c < 8; ++c) p.weight[static_cast<std::size_t>(c)] = static_cast<float>(point.weight[c]);
    partial_.push_back(p);
    compact_[i].row[0] = -static_cast<std::int32_t>(partial_.size());
  }
}

std::size_t BandInterpolation::memory_bytes() const {
  return compact_.capacity() * sizeof(Compact) + partial_.capacity() * sizeof(Partial);
}

BandMultigrid::BandMultigrid(const NarrowBand& fine, double z_min, const StageProgress& progress) {
  if (!(z_min > 0.0)) throw std::invalid_argument("multigrid: the shift must be positive");
  levels_.emplace_back();
  levels_.back().band = &fine;
  std::vector<Vec3> finer_cps = fine.closest_points();
  while (static_cast<int>(levels_.size()) < kMaxLevels) {
    const NarrowBand& finer = *levels_.back().band;
    const double h = finer.grid().h();
    if (z_min * h * h >= kCoarseEnough || finer.size() < kSmallestBand) break;
    // Each level has about a quarter of the voxels of the one before: shares 3/4, 3/16, ...
    const double done = 1.0 - std::pow(0.25, static_cast<double>(levels_.size() - 1));
    const StageProgress level_progress = progress.part(0.9 * done, 0.9 * (1.0 - 0.25 * (1.0 - done)));
    const SampledSurface sampled(surface_samples(finer, finer_cps));
    level_progress.advance(0.1);
    BandOptions band_options{kCoarseDeltaInH, ClosestPointRule::exact, level_progress.part(0.1, 0.8)};
    auto coarse =
        std::make_unique<NarrowBand>(build_band(sampled, covering_grid(sampled, 2.0 * h), band_options));
    std::vector<Vec3> cps = coarse->closest_points();
    Level level;
    level.from_finer = BandInterpolation(finer, cps);
    levels_.back().to_coarser = BandInterpolation(*coarse, finer_cps);
    level_progress.advance(1.0);
    level.owned = std::move(coarse);
    level.band = level.owned.get();
    levels_.push_back(std::move(level));
    finer_cps = std::move(cps);
    release_free_memory();  // the coarse band's scan, in many small blocks
  }

  progress.advance(0.9);
  for (Level& level : levels_) {
    progress.check();
    const NarrowBand& band = *level.band;
    const std::size_t n = band.size();
    level.inverse_diagonal_base.resize(n);
    const auto stencils = band.stencils();
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
      // A ghost whose stencil includes v itself puts weight back on the diagonal.
      double self = 0.0;
      for (int k = 0; k < NarrowBand::kNeighbors; ++k) {
        const auto nb = static_cast<std::size_t>(band.neighbor(v, k));
        if (nb < n) continue;
        const GhostStencil& s = stencils[nb - n];
        for (int c = 0; c < 8; ++c)
          if (static_cast<std::size_t>(s.corner(c)) == v) self += s.weight(c);
      }
      level.inverse_diagonal_base[v] = static_cast<float>(6.0 - self);
    });
    for (std::size_t v = 0; v < n; ++v) {
      const Coord c = band.voxels()[v];
      level.colours[(c.i + c.j + c.k) & 1].push_back(static_cast<std::uint32_t>(v));
    }
    level.x.assign(band.extended_size(), 0.0);
    level.b.assign(n, 0.0);
    level.r.assign(band.extended_size(), 0.0);
    level.averaged.assign(n, 0.0);
  }
}

std::size_t BandMultigrid::memory_bytes() const {
  std::size_t bytes = 0;
  for (const Level& l : levels_) {
    if (l.owned) bytes += l.owned->memory_bytes();
    bytes += (l.inverse_diagonal_base.capacity() + l.relaxation[0].inverse_diagonal.capacity() +
              l.relaxation[1].inverse_diagonal.capacity() + l.x.capacity() + l.colours[0].capacity() +
              l.colours[1].capacity() + l.b.capacity() + l.r.capacity() + l.averaged.capacity()) *
                 sizeof(float) +
             l.from_finer.memory_bytes() + l.to_coarser.memory_bytes();
  }
  return bytes + solution_.capacity() * sizeof(double);
}

std::size_t BandMultigrid::last_level_for(double z) const {
  std::size_t l = 0;
  while (l + 1 < levels_.size()) {
    const double h = levels_[l].band->grid().h();
    if (z * h * h >= kCoarseEnough) break;
    ++l;
  }
  return l;
}

double BandMultigrid::residual(Level& level, double z) {
  const NarrowBand& band = *level.band;
  band.fill_ghosts(level.x);
  const auto inv_h2 = static_cast<float>(1.0 / (band.grid().h() * band.grid().h()));
  const auto zf = static_cast<float>(z);
  return parallel_max(band.size(), [&](std::size_t v) {
    float sum = 0.0f;
    for (int k = 0; k < NarrowBand::kNeighbors; ++k) sum += level.x[band.neighbor(v, k)];
    const float xv = level.x[v];
    const float r = level.b[v] - (zf * xv - (sum - 6.0f * xv) * inv_h2);
    level.r[v] = r;
    return static_cast<double>(std::abs(r));
  });
}

const std::vector<float>& BandMultigrid::Level::inverse_diagonal(double z) {
  for (Relaxation& cached : relaxation)
    if (cached.z == z && !cached.inverse_diagonal.empty()) return cached.inverse_diagonal;
  std::swap(relaxation[0], relaxation[1]);
  Relaxation& fresh = relaxation[0];
  fresh.z = z;
  fresh.inverse_diagonal.resize(inverse_diagonal_base.size());
  const double inv_h2 = 1.0 / (band->grid().h() * band->grid().h());
  for_each_index(fresh.inverse_diagonal.size(), [&](std::size_t v) {
    fresh.inverse_diagonal[v] = static_cast<float>(1.0 / (z + inverse_diagonal_base[v] * inv_h2));
  });
  return fresh.inverse_diagonal;
}

void BandMultigrid::smooth(Level& level, double z, int sweeps, bool from_zero) {
  const NarrowBand& band = *level.band;
  const auto inv_h2 = static_cast<float>(1.0 / (band.grid().h() * band.grid().h()));
  const auto zf = static_cast<float>(z);
  const std::vector<float>& inverse_diagonal = level.inverse_diagonal(z);
  for (int s = 0; s < sweeps; ++s)
    for (int colour = 0; colour < 2; ++colour) {
      const auto& set = level.colours[colour];
      if (from_zero && s == 0 && colour == 0) {
        // x and its ghosts are all 0: the first half sweep needs no neighbours.
        for_each_index(set.size(), [&](std::size_t i) {
          const std::size_t v = set[i];
          level.x[v] = level.b[v] * inverse_diagonal[v];
        });
        continue;
      }
      // A voxel's 6 neighbours have the other parity: only those ghosts need fresh values.
      band.fill_ghosts(level.x, 1 - colour);
      for_each_index(set.size(), [&](std::size_t i) {
        const std::size_t v = set[i];
        float sum = 0.0f;
        for (int k = 0; k < NarrowBand::kNeighbors; ++k) sum += level.x[band.neighbor(v, k)];
        const float xv = level.x[v];
        const float r = level.b[v] - (zf * xv - (sum - 6.0f * xv) * inv_h2);
        level.x[v] = xv + r * inverse_diagonal[v];
      });
    }
}

void BandMultigrid::v_cycle(std::size_t l, std::size_t last, double z) {
  Level& fine = levels_[l];
  if (l == last) {
    if (l == 0) {
      smooth(fine, z, kSmoothingSweeps, true);
      return;
    }
    // The coarsest band is small: smooth it until its residual has dropped 1000-fold. Where coarsening
    // stopped at the size limit rather than at z h^2 >= 8, that takes more than a few sweeps.
    const double target = 1e-3 * residual(fine, z);
    for (int sweeps = 0; sweeps < kMaxCoarsestSweeps; sweeps += kCoarsestSweeps) {
      smooth(fine, z, kCoarsestSweeps, sweeps == 0);
      if (residual(fine, z) <= target) break;
    }
    return;
  }
  smooth(fine, z, kSmoothingSweeps, true);
  residual(fine, z);
  const NarrowBand& band = *fine.band;
  band.fill_ghosts(fine.r);
  for_each_index(band.size(), [&](std::size_t v) {
    float sum = 0.0f;
    for (int k = 0; k < NarrowBand::kNeighbors; ++k) sum += fine.r[band.neighbor(v, k)];
    fine.averaged[v] = 0.5f * fine.r[v] + sum * (1.0f / 12.0f);
  });
  Level& coarse = levels_[l + 1];
  for_each_index(coarse.band->size(),
                 [&](std::size_t v) { coarse.b[v] = coarse.from_finer.at<float>(v, fine.averaged); });
  std::fill(coarse.x.begin(), coarse.x.end(), 0.0f);
  v_cycle(l + 1, last, z);
  for_each_index(fine.band->size(),
                 [&](std::size_t v) { fine.x[v] += fine.to_coarser.at<float>(v, coarse.x); });
  smooth(fine, z, kSmoothingSweeps, false);
}

MultigridSolveReport BandMultigrid::solve(double z, std::span<const double> b, std::span<double> x,
                                          double residual_tolerance, int max_cycles,
                                          std::span<const double> operator_of_x) {
  Level& top = levels_.front();
  const std::size_t n = top.band->size();
  if (b.size() != n || x.size() != n || (!operator_of_x.empty() && operator_of_x.size() != n))
    throw std::invalid_argument("multigrid: one value per band voxel");
  // Defect correction: the residual of the double iterate, a float V-cycle for its correction.
  const NarrowBand& band = *top.band;
  solution_.resize(band.extended_size());
  std::copy(x.begin(), x.end(), solution_.begin());
  const double inv_h2 = 1.0 / (band.grid().h() * band.grid().h());
  const std::size_t last = last_level_for(z);
  MultigridSolveReport report;
  for (;;) {
    if (report.cycles == 0 && !operator_of_x.empty()) {
      report.residual = parallel_max(n, [&](std::size_t v) {
        const double r = b[v] - operator_of_x[v];
        top.b[v] = static_cast<float>(r);
        return std::abs(r);
      });
    } else {
      band.fill_ghosts(solution_);
      report.residual = parallel_max(n, [&](std::size_t v) {
        double sum = 0.0;
        for (int k = 0; k < NarrowBand::kNeighbors; ++k) sum += solution_[band.neighbor(v, k)];
        const double r = b[v] - (z * solution_[v] - (sum - 6.0 * solution_[v]) * inv_h2);
        top.b[v] = static_cast<float>(r);
        return std::abs(r);
      });
    }
    report.converged = report.residual <= residual_tolerance;
    if (report.converged || report.cycles >= max_cycles || !std::isfinite(report.residual)) break;
    std::fill(top.x.begin(), top.x.end(), 0.0f);
    progress_.advance(0.0);
    v_cycle(0, last, z);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) { solution_[v] += top.x[v]; });
    ++report.cycles;
  }
  std::copy(solution_.begin(), solution_.begin() + static_cast<std::ptrdiff_t>(n), x.begin());
  return report;
}

}  // namespace poreshell
