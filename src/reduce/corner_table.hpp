#pragma once
// The mesh the edge collapses change (edge_collapse.cpp, placed_collapse.cpp): a corner table, each
// vertex's valence, the triangles removed, and the parts of the mesh that workers collapse at once.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/run_monitor.hpp"
#include "geometry/mesh.hpp"
#include "reduce/collapse_bounds.hpp"  // next_corner(), previous_corner()
#include "reduce/edge_collapse.hpp"    // CollapsedMesh

namespace poreshell {

class CornerTable {
 protected:
  // Each corner's vertex and the corner across the edge it faces, side by side: walking around a
  // vertex reads both, and on a mesh of a million triangles that walk is mostly cache misses.
  struct Corner {
    std::int32_t vertex, opposite;
  };

  // `opposite` is opposite_corners(mesh).
  void build_table(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite) {
    const std::size_t nf = mesh.triangles.size();
    corners_.resize(3 * nf);
    vertex_corner_.assign(mesh.vertices.size(), -1);
    valence_.assign(mesh.vertices.size(), 0);
    dead_.assign(nf, 0);
    // A closed manifold's vertex has as many triangles as edges: its valence counts its corners.
    for (std::size_t f = 0; f < nf; ++f) {
      const auto& t = mesh.triangles[f];
      for (int k = 0; k < 3; ++k) {
        corners_[3 * f + k] = {t[k], opposite[3 * f + k]};
        vertex_corner_[static_cast<std::size_t>(t[k])] = static_cast<std::int32_t>(3 * f + k);
        ++valence_[static_cast<std::size_t>(t[k])];
      }
    }
  }

  std::int32_t vertex(std::int32_t c) const { return corners_[static_cast<std::size_t>(c)].vertex; }
  std::int32_t across(std::int32_t c) const { return corners_[static_cast<std::size_t>(c)].opposite; }

  // The corners of v, turning around it.
  void fan(std::int32_t v, std::vector<std::int32_t>& out) const {
    out.clear();
    const std::int32_t first = vertex_corner_[static_cast<std::size_t>(v)];
    std::int32_t c = first;
    do {
      out.push_back(c);
      c = next_corner(across(next_corner(c)));
    } while (c != first);
  }

  // The link condition for collapsing corner c's vertex v0 onto v1, its next: they share no
  // neighbour but vl and vr (v0's neighbours carry `stamp` in `mark`). A valence-3 vertex beside the
  // edge would be left with two triangles back to back.
  bool link_ok(std::int32_t c, const std::vector<std::uint32_t>& mark, std::uint32_t stamp,
               std::vector<std::int32_t>& scratch) const {
    const std::int32_t v1 = vertex(next_corner(c)), vl = vertex(previous_corner(c));
    const std::int32_t vr = vertex(across(previous_corner(c)));
    if (vl == vr || valence_[static_cast<std::size_t>(vl)] <= 3 ||
        valence_[static_cast<std::size_t>(vr)] <= 3)
      return false;
    fan(v1, scratch);
    for (const std::int32_t k : scratch) {
      const std::int32_t n = vertex(next_corner(k));
      if (n != vl && n != vr && mark[static_cast<std::size_t>(n)] == stamp) return false;
    }
    return true;
  }

  std::int32_t corner_in(std::int32_t triangle, std::int32_t v) const {
    for (std::int32_t k = 3 * triangle; k < 3 * triangle + 3; ++k)
      if (vertex(k) == v) return k;
    throw std::runtime_error("mesh decimation: a corner table lost a vertex");
  }

  // Collapses corner c's vertex v0 onto v1 in the table; `fan0` is v0's fan before. The two triangles
  // of the edge go, those across their outer edges face each other, v0's other triangles end at v1.
  void collapse_corners(std::int32_t c, const std::vector<std::int32_t>& fan0) {
    const std::int32_t v0 = vertex(c), v1 = vertex(next_corner(c)), vl = vertex(previous_corner(c));
    const std::int32_t e = across(previous_corner(c));  // vr's corner
    const std::int32_t vr = vertex(e), left = c / 3, right = e / 3;
    const std::int32_t right0 = previous_corner(e), right1 = next_corner(e);  // v0's and v1's
    const std::int32_t a = across(c), b = across(next_corner(c)), f = across(right0), g = across(right1);
    corners_[static_cast<std::size_t>(a)].opposite = b;
    corners_[static_cast<std::size_t>(b)].opposite = a;
    corners_[static_cast<std::size_t>(f)].opposite = g;
    corners_[static_cast<std::size_t>(g)].opposite = f;
    for (const std::int32_t k : fan0)
      if (k / 3 != left && k / 3 != right) corners_[static_cast<std::size_t>(k)].vertex = v1;
    dead_[static_cast<std::size_t>(left)] = dead_[static_cast<std::size_t>(right)] = 1;
    vertex_corner_[static_cast<std::size_t>(v0)] = -1;
    vertex_corner_[static_cast<std::size_t>(v1)] = corner_in(a / 3, v1);
    vertex_corner_[static_cast<std::size_t>(vl)] = corner_in(a / 3, vl);
    vertex_corner_[static_cast<std::size_t>(vr)] = corner_in(f / 3, vr);
    // v1 gains v0's neighbours but the shared vl and vr (the link condition); they lose v0.
    valence_[static_cast<std::size_t>(v1)] += valence_[static_cast<std::size_t>(v0)] - 4;
    --valence_[static_cast<std::size_t>(vl)];
    --valence_[static_cast<std::size_t>(vr)];
  }

  // Slabs of `points` along their longest side, of equal vertex counts, into owner_; a vertex with a
  // neighbour in another slab is owned by no part (-1). Returns each part's triangles (those whose
  // first vertex it owns).
  std::vector<std::size_t> split_into_parts(int parts, const std::vector<Vec3>& points) {
    owner_.assign(points.size(), 0);
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Vec3& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    // Vertex i of the order along the axis (ties by index: a total order, so the same slabs on any
    // thread count) goes to part i * parts / n. Only the slabs' bounds are needed, not the order: each
    // is selected from what the one before left (the bunny's shell, 750 k vertices: 0.03 s, where
    // sorting them all took 0.08 s).
    std::vector<std::pair<double, std::int32_t>> keyed(points.size());
    tbb::parallel_for(std::size_t{0}, keyed.size(), [&](std::size_t v) {
      keyed[v] = {points[v][axis], static_cast<std::int32_t>(v)};
    });
    const std::size_t n = keyed.size();
    std::size_t begin = 0;
    for (int part = 0; part < parts; ++part) {
      // The first i with i * parts / n == part + 1.
      const std::size_t end =
          part + 1 == parts ? n : ((part + 1) * n + parts - 1) / static_cast<std::size_t>(parts);
      if (end < n) std::nth_element(keyed.begin() + begin, keyed.begin() + end, keyed.end());
      tbb::parallel_for(begin, end,
                        [&](std::size_t i) { owner_[static_cast<std::size_t>(keyed[i].second)] = part; });
      begin = end;
    }
    std::vector<char> cut(points.size(), 0);
    for (std::size_t f = 0; f < dead_.size(); ++f) {
      const std::int32_t a = corners_[3 * f].vertex, b = corners_[3 * f + 1].vertex,
                         c = corners_[3 * f + 2].vertex;
      if (owner_[a] != owner_[b] || owner_[b] != owner_[c]) cut[a] = cut[b] = cut[c] = 1;
    }
    std::vector<std::size_t> share(static_cast<std::size_t>(parts), 0);
    for (std::size_t f = 0; f < dead_.size(); ++f)
      ++share[static_cast<std::size_t>(owner_[corners_[3 * f].vertex])];
    for (std::size_t v = 0; v < cut.size(); ++v)
      if (cut[v]) owner_[v] = -1;
    return share;
  }

  // The vertices along the cuts between parts and their neighbours: where the last worker, owning
  // every vertex, starts (owner_ still the parts').
  std::vector<char> along_cuts() const {
    std::vector<char> candidate(vertex_corner_.size(), 0);
    std::vector<std::int32_t> around;
    for (std::size_t v = 0; v < vertex_corner_.size(); ++v)
      if (owner_[v] < 0 && vertex_corner_[v] >= 0) {
        candidate[v] = 1;
        fan(static_cast<std::int32_t>(v), around);
        for (const std::int32_t c : around) candidate[static_cast<std::size_t>(vertex(next_corner(c)))] = 1;
      }
    return candidate;
  }

  // Parts for meshes from this many triangles (below, a reduction takes tens of milliseconds). 4
  // parts took 12.5 s on the bunny's 1.5 M triangles on 2 cores, 2 and 8 parts 14.4 s (docs/benchmarks.md
  // "Triangle reduction on flat arrays"); the count is fixed, not the thread count, so that the
  // result is too.
  static constexpr std::size_t kParallelTriangles = 10'000;
  static constexpr int kParts = 4;

  // A collapser's one run: collapses until at most `target` triangles are left or none passes its
  // rules. A mesh of at least kParallelTriangles first runs kParts workers at once on slabs of equal
  // vertex counts along its longest side (`points`), each to its share of the collapses; the same slabs
  // whatever the thread count, so the same result. make_worker(part, questions) makes a worker for a part
  // of about `questions` triangles; collapse_until(worker, quota, candidate, loop) runs it from the
  // candidate vertices and returns how many triangles went. The last worker, owning every vertex, starts
  // from the vertices along the cuts and those still in a part's queue (marked `left_in_queue`); the
  // others failed every collapse on a fan that has not changed since, as in one run.
  template <class MakeWorker, class CollapseUntil>
  void run_in_parts(const std::vector<Vec3>& points, std::size_t target, char left_in_queue,
                    CollapseCounts& counts, const StageProgress& progress, MakeWorker make_worker,
                    CollapseUntil collapse_until) {
    const std::size_t live = dead_.size();  // the collapser's one call: none is dead yet
    if (live <= target) return;
    LoopProgress loop(progress, (live - target) / 2);
    std::vector<char> candidate(points.size(), 1);
    if (live < kParallelTriangles) {
      auto worker = make_worker(0, live);
      collapse_until(worker, live - target, candidate, loop);
      counts += worker.counts;
      progress.check();
      return;
    }
    const std::vector<std::size_t> share = split_into_parts(kParts, points);
    std::vector<std::size_t> removed(kParts, 0);
    std::vector<std::vector<std::int32_t>> queued(kParts);
    std::vector<CollapseCounts> part_counts(kParts);
    // Each thread that is free takes the next part: the parts' times differ by up to a third (the
    // bunny's shell: 1.07-1.39 s), and parallel_for's halves alone would pair them as {0, 1} and
    // {2, 3} whatever their times. A part's collapses are its own, so who runs it changes nothing.
    std::atomic<int> next_part = 0;
    tbb::parallel_for(0, kParts, [&](int) {
      const int part = next_part++;
      const auto p = static_cast<std::size_t>(part);
      auto worker = make_worker(part, share[p]);
      // Each part's share of the triangles to remove, a little short: the last worker then has
      // enough left to bring the cuts, still at full resolution, down with the rest.
      const auto quota = static_cast<std::size_t>(0.98 * static_cast<double>(live - target) *
                                                  static_cast<double>(share[p]) / static_cast<double>(live));
      removed[p] = collapse_until(worker, quota, candidate, loop);
      queued[p] = worker.queue.vertices();
      part_counts[p] = worker.counts;
    });
    candidate = along_cuts();
    for (const auto& vertices : queued)
      for (const std::int32_t v : vertices)
        if (!candidate[static_cast<std::size_t>(v)]) candidate[static_cast<std::size_t>(v)] = left_in_queue;
    std::fill(owner_.begin(), owner_.end(), 0);
    const std::size_t all = std::accumulate(removed.begin(), removed.end(), std::size_t{0});
    auto last = make_worker(0, live);
    collapse_until(last, live - all > target ? live - all - target : 0, candidate, loop);
    for (const CollapseCounts& c : part_counts) counts += c;
    counts += last.counts;
    progress.check();
  }

  // The live triangles in their order, and each carried point's carrier among them: the points that a
  // triangle carries are a list from first_point[triangle] through next_point; those from `vertices`
  // on are not vertices and are left out.
  CollapsedMesh live_mesh(const std::vector<std::int32_t>& first_point,
                          const std::vector<std::int32_t>& next_point, std::size_t vertices) const {
    CollapsedMesh out;
    out.carrier.assign(vertices, -1);
    for (std::size_t f = 0; f < dead_.size(); ++f) {
      if (dead_[f]) continue;
      const auto index = static_cast<std::int32_t>(out.triangles.size());
      for (std::int32_t p = first_point[f]; p >= 0; p = next_point[static_cast<std::size_t>(p)])
        if (static_cast<std::size_t>(p) < vertices) out.carrier[static_cast<std::size_t>(p)] = index;
      out.triangles.push_back(
          {corners_[3 * f].vertex, corners_[3 * f + 1].vertex, corners_[3 * f + 2].vertex});
    }
    return out;
  }

  std::vector<Corner> corners_;
  std::vector<std::int32_t> vertex_corner_;  // a corner of each vertex in a live triangle; -1: removed
  std::vector<std::int32_t> valence_;        // per vertex
  std::vector<char> dead_;                   // per triangle
  std::vector<std::int32_t> owner_;          // per vertex: the part whose worker may move it; -1: none
};

}  // namespace poreshell
