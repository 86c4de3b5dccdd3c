#pragma once
// Geometric multigrid for the shifted closest-point Laplacian on the band,
//   (z - Delta_h) x = b,  z > 0,  ghosts of x by closest-point interpolation (eliminated),
// the building block of the fast solver (docs/solver.md).
//
// Coarse levels are bands of the surface on grids of spacing 2h, 4h, ..., the surface known by the
// finer level's closest points (no search of the input surface: the hierarchy needs only the fine
// band). A band value stands
// for the value at its closest point on the surface, so values move between levels through closest
// points: restriction interpolates the finer residual at the coarse voxel's closest point, prolongation
// the coarse correction at the finer voxel's closest point (closest-point multigrid). The smoother is
// red-black Gauss-Seidel. The operator's rows sum to z with non-positive off-diagonals (trilinear weights are
// non-negative), so |x - x*|_inf <= |b - (z - L) x|_inf / z: the stopping rule bounds the error itself.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "band/band.hpp"
#include "core/trilinear.hpp"

namespace poreshell {

// Trilinear interpolation from a band's values at fixed points (the closest points of another level's
// voxels): the transfers between levels. Where the point's cell has all 8 corners in the band (nearly
// everywhere) it is stored like a GhostStencil with float fractions, 28 bytes; the few others keep
// their present corners with renormalised weights. Float: transfers carry corrections only.
class BandInterpolation {
 public:
  BandInterpolation() = default;
  BandInterpolation(const NarrowBand& from, std::span<const Vec3> points);

  template <class T>
  T at(std::size_t i, std::span<const T> values) const {
    const Compact& s = compact_[i];
    if (s.row[0] < 0) return partial_at(partial_[static_cast<std::size_t>(-s.row[0] - 1)], values);
    const auto along_x = [&](int r) {
      const T* v = values.data() + s.row[static_cast<std::size_t>(r)];
      return v[0] + s.t[0] * (v[1] - v[0]);
    };
    return trilinear_from_rows(along_x, static_cast<T>(s.t[1]), static_cast<T>(s.t[2]));
  }
  std::size_t memory_bytes() const;

 private:
  struct Compact {
    std::array<std::int32_t, 4> row{};  // as GhostStencil; row[0] < 0: partial_[-row[0] - 1]
    std::array<float, 3> t{};
  };
  struct Partial {
    std::array<std::int32_t, 8> corner{};
    std::array<float, 8> weight{};
  };
  template <class T>
  static T partial_at(const Partial& s, std::span<const T> values) {
    T v = 0;
    for (std::size_t c = 0; c < 8; ++c) v += s.weight[c] * values[static_cast<std::size_t>(s.corner[c])];
    return v;
  }

  std::vector<Compact> compact_;
  std::vector<Partial> partial_;
};

struct MultigridSolveReport {
  int cycles = 0;
  double residual = 0.0;  // max-norm residual at the end
  bool converged = false;
};

class BandMultigrid {
 public:
  // Builds coarse bands until a level's z_min h^2 >= 2 (Jacobi alone converges fast there) or the band
  // gets small. z_min: the smallest shift the caller will solve with.
  BandMultigrid(const NarrowBand& fine, double z_min, const StageProgress& progress = {});

  // Iterates V-cycles on x (initial guess in, solution out; band values only) until
  // |b - (z - L) x|_inf <= residual_tolerance or max_cycles. `operator_of_x`, where the caller has it:
  // (z - L) x of the guess, so that the first residual costs no operator (and no ghost) pass.
  // Checked (and reported without a fraction of its own) before every V-cycle of solve(): at 830 points
  // a time step takes up to 20 cycles of half a second.
  void set_progress(const StageProgress& progress) { progress_ = progress; }
  MultigridSolveReport solve(double z, std::span<const double> b, std::span<double> x,
                             double residual_tolerance, int max_cycles,
                             std::span<const double> operator_of_x = {});

  int level_count() const { return static_cast<int>(levels_.size()); }
  std::size_t voxels_on_level(int l) const { return levels_[static_cast<std::size_t>(l)].band->size(); }
  // Heap bytes held beyond the fine band itself (coarse bands, transfers, work arrays).
  std::size_t memory_bytes() const;

 private:
  struct Level {
    std::unique_ptr<NarrowBand> owned;  // coarse levels own their band; level 0 borrows the fine one
    const NarrowBand* band = nullptr;
    std::vector<float> inverse_diagonal_base;  // 6 - self weight: h^2 (diagonal - z)
    // 1 / diagonal of z - L for the last two shifts (a step alternates two): smoothing multiplies
    // instead of dividing.
    struct Relaxation {
      double z = 0.0;
      std::vector<float> inverse_diagonal;
    };
    Relaxation relaxation[2];
    const std::vector<float>& inverse_diagonal(double z);
    std::vector<std::uint32_t>
        colours[2];                // red-black sets, (i + j + k) even / odd: colour c reads ghosts of 1 - c
    BandInterpolation from_finer;  // restriction: into the finer band at this voxel's cp
    BandInterpolation to_coarser;  // prolongation: into the coarser band at this voxel's cp
    // Float: the cycles solve for corrections (solve() keeps the solution and its residual in double),
    // and their passes are memory-bound, so half the bytes is nearly half the time.
    std::vector<float> x, r;         // extended (band + ghosts)
    std::vector<float> b, averaged;  // band
  };

  // Red-black Gauss-Seidel; from_zero: x (and its ghosts) are 0 on entry.
  void smooth(Level& level, double z, int sweeps, bool from_zero);
  double residual(Level& level, double z);  // fills level.r, returns its max norm
  void v_cycle(std::size_t l, std::size_t last, double z);
  std::size_t last_level_for(double z) const;

  std::vector<Level> levels_;
  StageProgress progress_;
  std::vector<double> solution_;  // solve()'s iterate, band + ghosts, in double
};

}  // namespace poreshell
