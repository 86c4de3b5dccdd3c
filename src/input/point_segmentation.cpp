#include "input/point_segmentation.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "core/error.hpp"
#include "geometry/isosurface.hpp"
#include "geometry/mesh_surface.hpp"
#include "input/segmentation_domain.hpp"

namespace poreshell {
namespace {

double double_well(double psi) {  // F(psi) = (psi^2 - 1)^2 / 4
  const double s = psi * psi - 1.0;
  return 0.25 * s * s;
}

}  // namespace

std::unique_ptr<SampledLevelSet> segment_point_cloud(const std::vector<Vec3>& input_points,
                                                     const Triangles& input_triangles, const Grid& grid,
                                                     const SegmentationOptions& o, SegmentationStats* stats) {
  const double h = grid.h();
  if (!(o.band_in_h >= 3.0)) throw InputError("the segmentation band must be at least 3 h wide");
  if (!(o.epsilon_in_h > 0.0) || o.max_iterations < 0 || !(o.tolerance > 0.0))
    throw InputError("segmentation: epsilon, iterations and tolerance must be positive");
  SegmentationStats st;

  // (a) Fig. 8: densify the patches (the input's own, or each point's umbrella).
  const double tol = o.densify_tolerance_in_h * h;
  std::vector<Vec3> patch_points = input_points;
  std::vector<char> boundary;
  Triangles patches = input_triangles.empty() ? umbrella_patches(input_points, &boundary) : input_triangles;
  if (!input_triangles.empty()) boundary = boundary_vertices(input_points.size(), input_triangles);
  // Scans have holes (the bunny's base); the segmentation needs a closed surface, so cap them first.
  st.hole_caps = o.cap_holes ? cap_holes(patch_points, patches, boundary, 6) : 0;
  const std::vector<Vec3> points = densify_patches(patch_points, patches, tol);
  st.points = static_cast<std::int64_t>(points.size());
  const PointTree tree(points);

  // The sampling lattice: the grid's own points (an integer offset from its origin), wide enough for
  // the band, its ghost layer and the trilinear cells around them.
  Box box{points.front(), points.front()};
  for (const Vec3& p : points) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  const double width = o.band_in_h * h;
  const int margin = static_cast<int>(std::ceil(o.band_in_h)) + 3;
  std::array<int, 3> lo{}, dims{};
  for (int a = 0; a < 3; ++a) {
    lo[static_cast<std::size_t>(a)] =
        static_cast<int>(std::floor((box.min[a] - grid.origin()[a]) / h)) - margin;
    const int hi = static_cast<int>(std::ceil((box.max[a] - grid.origin()[a]) / h)) + margin;
    dims[static_cast<std::size_t>(a)] = hi - lo[static_cast<std::size_t>(a)] + 1;
  }
  const Grid lattice(grid.origin() + h * Vec3(lo[0], lo[1], lo[2]), h, dims);

  // (b) eq. (3.3) on the sparse band {g < width}, Dirichlet psi = +-1 on its ghost layer.
  const SegmentationDomain d = find_segmentation_domain(lattice, tree, width);
  const std::size_t n = d.band.size(), m = d.ghost.size();
  st.band_voxels = static_cast<std::int64_t>(n);
  st.ghost_voxels = static_cast<std::int64_t>(m);
  const std::vector<signed char> side = label_sides(lattice, d, 0.5 * h + tol, st.inside_voxels);
  std::int64_t inside_ghosts = 0;
  for (std::size_t g = 0; g < m; ++g) inside_ghosts += side[n + g] < 0;
  if (stats) *stats = st;
  if (st.inside_voxels == 0 && inside_ghosts == 0)
    throw InputError(
        "the paper's point-cloud route found no inside: the points do not enclose a volume at this "
        "resolution "
        "(a hole wider than about one voxel, or an open surface); use `point_route` direct, which needs no "
        "inside, or close the holes");

  const double eps = o.epsilon_in_h * h, eps2 = eps * eps;
  const double lambda = o.lambda_eps2 / eps2;
  std::vector<std::int32_t> neighbors(n * 6);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    const Coord c = lattice.coord(d.band[v]);
    for (std::size_t f = 0; f < 6; ++f) {
      const std::int64_t key = lattice.key(shifted(c, kFaceOffsets[f]));
      std::int64_t idx = find_key(d.band, key);
      if (idx < 0) idx = static_cast<std::int64_t>(n) + find_key(d.ghost, key);  // always one or the other
      neighbors[v * 6 + f] = static_cast<std::int32_t>(idx);
    }
  });
  std::vector<double> psi(n + m), next(n + m);
  double g_max = 0.0;
  for (std::size_t v = 0; v < n + m; ++v) {
    const double g = v < n ? d.band_g[v] : width;
    g_max = std::max(g_max, g);
    psi[v] = v < n ? side[v] * std::tanh(g / (std::sqrt(2.0) * eps)) : side[v];
  }
  next = psi;
  // Explicit Euler; stable for dt g (12/h^2 + 2/eps^2) < 2 (the Laplacian's and the double well's
  // largest rates); half of that.
  const double dt = 1.0 / (g_max * (12.0 / (h * h) + 2.0 / eps2));
  int it = 0;
  double change = 0.0;
  for (it = 1; it <= o.max_iterations; ++it) {
    change = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double worst) {
          for (std::size_t v = r.begin(); v < r.end(); ++v) {
            const double p = psi[v];
            double lap = -6.0 * p;
            for (std::size_t f = 0; f < 6; ++f) lap += psi[static_cast<std::size_t>(neighbors[v * 6 + f])];
            lap /= h * h;
            const double rate = -(p * p * p - p) / eps2 + lap + lambda * double_well(p);
            next[v] = p + dt * d.band_g[v] * rate;
            worst = std::max(worst, std::abs(next[v] - p));
          }
          return worst;
        },
        [](double a, double b) { return std::max(a, b); });
    std::swap(psi, next);
    if (change < o.tolerance) break;
  }
  st.iterations = std::min(it, o.max_iterations);
  st.last_change = change;
  st.dt = dt;
  st.epsilon = eps;
  st.lambda = lambda;

  // The zero level of psi (marching cubes over band and ghosts). The solid's far side, where the inner
  // ghost layer (-1) meets the background (+1), is a second, spurious sheet a band width from the points;
  // keep only the sheet near the points.
  std::vector<Coord> coords(n + m);
  for (std::size_t v = 0; v < n + m; ++v) coords[v] = lattice.coord(v < n ? d.band[v] : d.ghost[v - n]);
  TriangleMesh level = extract_isosurface(SparseField{&lattice, coords, psi, 1.0}, 0.0);
  TriangleMesh kept;
  kept.vertices = level.vertices;
  for (const auto& t : level.triangles) {
    const Vec3 centroid =
        (level.vertices[static_cast<std::size_t>(t[0])] + level.vertices[static_cast<std::size_t>(t[1])] +
         level.vertices[static_cast<std::size_t>(t[2])]) /
        3.0;
    if (tree.nearest(centroid).second < 0.5 * width) kept.triangles.push_back(t);
  }
  if (stats) *stats = st;
  if (kept.triangles.empty())
    throw InputError(
        "the paper's point-cloud route found no surface in the segmentation; use `point_route` direct");
  st.zero_level_triangles = static_cast<std::int64_t>(kept.triangles.size());
  for (const auto& t : kept.triangles)
    for (const std::int32_t v : t)
      st.zero_level_max_gap =
          std::max(st.zero_level_max_gap, tree.nearest(kept.vertices[static_cast<std::size_t>(v)]).second);

  // The discrete signed distance: the sign of psi, the exact distance to its zero level.
  const MeshSurface zero_level(kept);
  std::vector<std::pair<std::int64_t, double>> samples(n + m);
  tbb::parallel_for(std::size_t{0}, n + m, [&](std::size_t v) {
    const double dist = zero_level.distance(lattice.position(coords[v]));
    samples[v] = {lattice.key(coords[v]), psi[v] < 0.0 ? -dist : dist};
  });
  std::sort(samples.begin(), samples.end());
  std::vector<std::int64_t> keys(samples.size());
  std::vector<double> values(samples.size());
  for (std::size_t v = 0; v < samples.size(); ++v) std::tie(keys[v], values[v]) = samples[v];
  if (stats) *stats = st;
  // The zero level's triangles reach at most half an edge (< h) beyond their vertices.
  return std::make_unique<SampledLevelSet>(lattice, std::move(keys), std::move(values), points,
                                           st.zero_level_max_gap + h, &kept);
}

}  // namespace poreshell
