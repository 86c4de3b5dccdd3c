#include "shell/mesh_decimate.hpp"

// OpenMesh's DecimaterT does the reduction: halfedge collapses, least error quadric first, each
// made only where the link condition keeps the mesh manifold and the checks of ModBounded pass.
// Halfedge collapses do not move vertices, so every reduced vertex is an original one. The result
// is then checked independently with analyze_topology() and MeshSurface. All of OpenMesh stays in
// this file.
//
// The distance bound needs both directions. OpenMesh's ModHausdorff gives one: the original
// vertices stay within the tolerance of the reduced surface. Not the other: on poreshell's shells,
// triangles then bridge the concave rims of pores and fold over triangles that the original
// vertices find close instead, up to 7 times the tolerance off the original surface. So the
// centroid of every new triangle and the midpoint of every new edge are checked against the
// original surface as well; these are the points the result is measured at.

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModHausdorffT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <OpenMesh/Tools/Decimater/Observer.hh>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "geometry/mesh_surface.hpp"
#include "shell/printability.hpp"

namespace poreshell {
namespace {

constexpr double kMinAngleDegrees = 10.0;   // smallest angle of a new triangle
constexpr double kMaxNormalDegrees = 90.0;  // between a new triangle and the surface at its corners
constexpr int kMaxWalk = 16;                // steps across the original surface before searching all of it
// The result meets the bound by construction but for ModHausdorff, which looks only at the ring
// being collapsed. Should the measured distance exceed the bound all the same, the reduction is
// redone from the original with the tolerance scaled down by the overshoot.
constexpr int kAttempts = 3;

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<OpenMesh::DefaultTraitsDouble>;

// OpenMesh's triangle mesh with a faster is_collapse_ok(). The decimater asks it about every
// candidate collapse, some 40 per collapse made, and TriConnectivity's version is slow in Debian's
// build (a heap allocation and property-name assertions per call): over a third of the time. The
// decimater and its modules are templates over the mesh type, so they call this one; every
// collapse actually made is still checked with OpenMesh's own test.
class OMesh : public TriMesh {
 public:
  // The link condition: v0 and v1 share no neighbour but the two opposite vertices, otherwise the
  // collapse would make an edge with more than two triangles. Meshes with boundary, which
  // decimate_mesh() refuses, are left to OpenMesh.
  bool is_collapse_ok(HalfedgeHandle v0v1) {
    if (status(edge_handle(v0v1)).deleted()) return false;
    const HalfedgeHandle v1v0 = opposite_halfedge_handle(v0v1);
    const VertexHandle v0 = to_vertex_handle(v1v0), v1 = to_vertex_handle(v0v1);
    if (status(v0).deleted() || status(v1).deleted()) return false;
    if (is_boundary(v0) || is_boundary(v1)) return TriMesh::is_collapse_ok(v0v1);
    const VertexHandle vl = to_vertex_handle(next_halfedge_handle(v0v1));
    const VertexHandle vr = to_vertex_handle(next_halfedge_handle(v1v0));
    if (vl == vr) return false;
    // Rotating by hand: OpenMesh's circulators cost several times as much here.
    ring_.clear();
    for_each_neighbour(v1, [&](VertexHandle w) { ring_.push_back(w); });
    bool ok = true;
    for_each_neighbour(v0, [&](VertexHandle w) {
      if (w != vl && w != vr && std::find(ring_.begin(), ring_.end(), w) != ring_.end()) ok = false;
    });
    return ok;
  }

  void collapse(HalfedgeHandle v0v1) {
    if (!TriMesh::is_collapse_ok(v0v1))
      throw std::runtime_error("mesh decimation: a collapse failed OpenMesh's manifold test");
    TriMesh::collapse(v0v1);
  }

 private:
  template <class F>
  void for_each_neighbour(VertexHandle v, F&& f) const {
    const HalfedgeHandle first = halfedge_handle(v);
    HalfedgeHandle h = first;
    do {
      f(to_vertex_handle(h));
      h = next_halfedge_handle(opposite_halfedge_handle(h));
    } while (h != first);
  }

  std::vector<VertexHandle> ring_;  // scratch, kept to save an allocation per call
};

OMesh::Point to_point(const Vec3& p) {
  return {p.x(), p.y(), p.z()};
}
Vec3 to_vec(const OMesh::Point& p) {
  return {p[0], p[1], p[2]};
}

// Sine of the smallest angle, 2 area * shortest edge / (product of the edges): 0 for a degenerate
// triangle, sqrt(3)/2 for an equilateral one, whatever the scale.
double min_angle_sine(const OMesh::Point& a, const OMesh::Point& b, const OMesh::Point& c) {
  const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
  const double product = ab * bc * ca;
  if (!(product > 0.0)) return 0.0;
  return ((b - a) % (c - a)).norm() * std::min({ab, bc, ca}) / product;
}

// The original surface as the checks need it: vertex normals, and whether a point is near.
class Original {
 public:
  Original(const TriangleMesh& mesh, const MeshSurface& surface)
      : mesh_(mesh), surface_(surface), start_(mesh.vertices.size() + 1, 0) {
    for (const auto& t : mesh.triangles)
      for (const std::int32_t v : t) ++start_[v + 1];
    std::partial_sum(start_.begin(), start_.end(), start_.begin());
    around_.resize(start_.back());
    std::vector<std::int32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
      for (const std::int32_t v : mesh.triangles[f]) around_[fill[v]++] = static_cast<std::int32_t>(f);
    find_neighbours();
    bounds_.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) bounds_.push_back(bound(t));
    compute_normals();
  }

  const OMesh::Normal& normal(OMesh::VertexHandle v) const { return normals_[v.idx()]; }

  // Whether p is within the tolerance of the original surface. Starts from the triangles around
  // the anchors, original vertices next to p, and walks across edges towards p while that comes
  // closer: the reduced triangles are a few original ones across, so that usually settles it for a
  // fraction of the cost of searching the whole surface, which is done only where the walk gets
  // stuck. Exact either way.
  bool near(const Vec3& p, std::initializer_list<std::int32_t> anchors, double tolerance) const {
    const double tolerance2 = tolerance * tolerance;
    std::int32_t at = -1;  // start where a bounding sphere comes nearest
    double least_gap = std::numeric_limits<double>::infinity();
    for (const std::int32_t v : anchors)
      for (std::int32_t i = start_[v]; i < start_[v + 1]; ++i)
        if (const double g = gap(p, around_[i]); g < least_gap) {
          least_gap = g;
          at = around_[i];
        }
    double best = distance2(p, at);
    auto visit = [&](std::int32_t f) {
      if (const double g = gap(p, f); g * g >= best) return;
      if (const double d2 = distance2(p, f); d2 < best) {
        best = d2;
        at = f;
      }
    };
    for (const std::int32_t v : anchors)
      for (std::int32_t i = start_[v]; i < start_[v + 1] && best > tolerance2; ++i) visit(around_[i]);
    for (int step = 0; step < kMaxWalk && best > tolerance2; ++step) {
      const std::int32_t from = at;
      for (const std::int32_t f : neighbours_[from]) visit(f);
      if (at == from) break;
    }
    return best <= tolerance2 || surface_.distance(p) <= tolerance;
  }

 private:
  struct Bound {
    Vec3 center;
    double radius;  // of a sphere about center holding the triangle
    TriangleShape shape;
  };

  Bound bound(const std::array<std::int32_t, 3>& t) const {
    const Vec3 &a = mesh_.vertices[t[0]], &b = mesh_.vertices[t[1]], &c = mesh_.vertices[t[2]];
    const Vec3 center = (a + b + c) / 3.0;
    const double radius = std::max({(a - center).norm(), (b - center).norm(), (c - center).norm()});
    return {center, radius, classify_triangle(a, b, c)};
  }
  // A lower bound on the distance from p to triangle f.
  double gap(const Vec3& p, std::int32_t f) const {
    return std::max((p - bounds_[f].center).norm() - bounds_[f].radius, 0.0);
  }
  double distance2(const Vec3& p, std::int32_t f) const {
    const auto& t = mesh_.triangles[f];
    const Vec3 q = closest_point_on_triangle(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]],
                                             mesh_.vertices[t[2]], bounds_[f].shape);
    return (q - p).squaredNorm();
  }

  // The triangles across the edges of each triangle, from the edges sorted by their vertices.
  void find_neighbours() {
    std::vector<std::pair<std::uint64_t, std::int32_t>> edges;  // (edge, triangle)
    edges.reserve(3 * mesh_.triangles.size());
    for (std::size_t f = 0; f < mesh_.triangles.size(); ++f) {
      const auto& t = mesh_.triangles[f];
      for (int i = 0; i < 3; ++i) {
        const auto a = static_cast<std::uint32_t>(std::min(t[i], t[(i + 1) % 3]));
        const auto b = static_cast<std::uint32_t>(std::max(t[i], t[(i + 1) % 3]));
        edges.emplace_back((std::uint64_t{a} << 32) | b, static_cast<std::int32_t>(f));
      }
    }
    std::sort(edges.begin(), edges.end());
    neighbours_.assign(mesh_.triangles.size(), {-1, -1, -1});
    std::vector<int> filled(mesh_.triangles.size(), 0);
    for (std::size_t i = 0; i + 1 < edges.size(); ++i)
      if (edges[i].first == edges[i + 1].first) {  // closed and manifold: two triangles an edge
        const std::int32_t f = edges[i].second, g = edges[i + 1].second;
        neighbours_[f][filled[f]++] = g;
        neighbours_[g][filled[g]++] = f;
        ++i;
      }
  }

  // Each corner weighted by its angle, so that the slivers of an isosurface mesh count for little.
  void compute_normals() {
    normals_.assign(mesh_.vertices.size(), OMesh::Normal(0.0, 0.0, 0.0));
    for (const auto& t : mesh_.triangles) {
      const std::array<OMesh::Point, 3> p = {to_point(mesh_.vertices[t[0]]), to_point(mesh_.vertices[t[1]]),
                                             to_point(mesh_.vertices[t[2]])};
      const OMesh::Normal n = ((p[1] - p[0]) % (p[2] - p[0])).normalize_cond();
      for (int i = 0; i < 3; ++i) {
        const OMesh::Point e1 = (p[(i + 1) % 3] - p[i]).normalize_cond();
        const OMesh::Point e2 = (p[(i + 2) % 3] - p[i]).normalize_cond();
        normals_[t[i]] += std::acos(std::clamp(e1 | e2, -1.0, 1.0)) * n;
      }
    }
    for (OMesh::Normal& n : normals_) n.normalize_cond();
  }

  const TriangleMesh& mesh_;
  const MeshSurface& surface_;
  std::vector<std::int32_t> start_, around_;  // triangles around vertex v: around_[start_[v], start_[v + 1])
  std::vector<std::array<std::int32_t, 3>> neighbours_;  // triangles across the edges
  std::vector<Bound> bounds_;
  std::vector<OMesh::Normal> normals_;
};

// Recent answers of Original::near() for a triangle or an edge of original vertices: they never
// change for a given tolerance, and DecimaterT rates a vertex's collapses again after every
// collapse next to it, asking many of the same questions. Direct-mapped and of bounded size: a miss
// costs the question, never a different answer.
class NearCache {
 public:
  explicit NearCache(std::size_t triangles)
      : slots_(std::min(std::bit_ceil(2 * triangles + 1), std::size_t{1} << 20)) {}

  // Triangle (a, b, c), or edge (a, b) with c = -1, in any order.
  template <class Ask>
  bool get(std::int32_t a, std::int32_t b, std::int32_t c, Ask&& ask) {
    std::array<std::int32_t, 3> key = {a, b, c};
    std::sort(key.begin(), key.end());
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const std::int32_t k : key) h = (h ^ static_cast<std::uint32_t>(k)) * 0xff51afd7ed558ccdull;
    Slot& slot = slots_[(h >> 32) & (slots_.size() - 1)];
    if (slot.key[0] != key[0] || slot.key[1] != key[1] || slot.key[2] != key[2]) {
      slot.key = key;
      slot.near = ask();
    }
    return slot.near;
  }

 private:
  struct Slot {
    std::array<std::int32_t, 3> key = {-2, -2, -2};
    bool near = false;
  };
  std::vector<Slot> slots_;
};

// The one module: the priority is the error quadric of a collapse (OpenMesh's ModQuadric), and a
// collapse is illegal unless
// - the original vertices stay within the tolerance of the new triangles (OpenMesh's ModHausdorff);
// - no new triangle has an angle below the minimum, unless one of those it replaces had one at
//   least as small: collapsing next to a sliver of the input is how it goes away, so slivers must
//   not freeze their neighbourhood (OpenMesh's ModAspectRatio compares against ratios cached
//   before other collapses moved their corners, and ModRoundness skips a triangle of the ring);
// - no new triangle faces away from the original surface at its corners;
// - the centroids of the new triangles and the midpoints of the new edges are within the
//   tolerance of the original surface.
// One module rather than one per rule, so that the costly checks are made lazily (see choose()).
class ModBounded : public OpenMesh::Decimater::ModBaseT<OMesh> {
 public:
  using Base = OpenMesh::Decimater::ModBaseT<OMesh>;
  using Handle = OpenMesh::Decimater::ModHandleT<ModBounded>;

  explicit ModBounded(OMesh& mesh)
      : Base(mesh, false), quadric_(mesh), hausdorff_(mesh), cache_(mesh.n_faces()) {}

  const std::string& name() const override {
    static const std::string name("Bounded");
    return name;
  }
  void set_bounds(const Original* original, double tolerance) {
    original_ = original;
    tolerance_ = tolerance;
    hausdorff_.set_tolerance(tolerance);
  }

  void initialize() override {
    quadric_.initialize();
    hausdorff_.initialize();
    sines_.resize(mesh().n_faces());
    for (const OMesh::FaceHandle f : mesh().faces()) update_sine(f);
  }
  void postprocess_collapse(const CollapseInfo& ci) override {
    quadric_.postprocess_collapse(ci);
    hausdorff_.postprocess_collapse(ci);
    for (const OMesh::FaceHandle f : mesh().vf_range(ci.v1)) update_sine(f);
    ++collapses_;
  }

  float collapse_priority(const CollapseInfo& ci) override {
    if (ci.v0 != vertex_ || collapses_ != vertex_collapses_) choose(ci.v0);
    return ci.v0v1 == chosen_ ? chosen_error_ : float(ILLEGAL_COLLAPSE);
  }

 private:
  struct Corners {
    std::array<OMesh::VertexHandle, 3> v;
    std::array<OMesh::Point, 3> p;
    int kept = 0;  // index of v1
  };

  // Rates all collapses of v0 at once, least quadric first, and keeps the first that passes the
  // checks; the others are refused. DecimaterT would keep the least legal one anyway, and the checks
  // cost far more than the quadric. (DecimaterT asks about a vertex's collapses one after
  // another, so this runs once per vertex and round; it stays right however it is asked.)
  void choose(OMesh::VertexHandle v0) {
    OMesh& m = mesh();
    vertex_ = v0;
    vertex_collapses_ = collapses_;
    chosen_.reset();
    candidates_.clear();
    for (const OMesh::HalfedgeHandle h : m.voh_range(v0)) {
      if (!m.is_collapse_ok(h)) continue;
      const CollapseInfo ci(m, h);
      // DecimaterT's own refusal: the collapse would leave two triangles back to back.
      if (ci.vl.is_valid() && ci.vr.is_valid() && m.find_halfedge(ci.vl, ci.vr).is_valid() &&
          m.valence(ci.vl) == 3 && m.valence(ci.vr) == 3)
        continue;
      // Round-off can make the quadric of a flat collapse negative, which DecimaterT takes as illegal.
      candidates_.emplace_back(std::max(quadric_.collapse_priority(ci), 0.0f), h.idx());
    }
    std::sort(candidates_.begin(), candidates_.end());  // ties by halfedge: deterministic
    for (const auto& [error, h] : candidates_) {
      const CollapseInfo ci(m, OMesh::HalfedgeHandle(h));
      if (shape_ok(ci) && near_ok() && hausdorff_.collapse_priority(ci) >= 0.0f) {
        chosen_ = ci.v0v1;
        chosen_error_ = error;
        return;
      }
    }
  }

  // Angles and normals of the triangles the collapse changes; keeps them in ring_ for near_ok().
  bool shape_ok(const CollapseInfo& ci) {
    OMesh& m = mesh();
    double before = 1.0;
    for (const OMesh::FaceHandle f : m.vf_range(ci.v0)) before = std::min(before, sines_[f.idx()]);
    const double least = std::min(min_sine_, before);
    ring_.clear();
    for (const OMesh::FaceHandle f : m.vf_range(ci.v0)) {
      if (f == ci.fl || f == ci.fr) continue;  // removed by the collapse
      Corners c;
      int k = 0;
      for (const OMesh::VertexHandle u : m.fv_range(f)) {
        if (u == ci.v0) c.kept = k;
        c.v[k] = u == ci.v0 ? ci.v1 : u;
        c.p[k++] = u == ci.v0 ? ci.p1 : m.point(u);
      }
      if (min_angle_sine(c.p[0], c.p[1], c.p[2]) < least) return false;
      const OMesh::Normal n = ((c.p[1] - c.p[0]) % (c.p[2] - c.p[0])).normalize_cond();
      for (const OMesh::VertexHandle u : c.v)
        if ((original_->normal(u) | n) < min_cos_) return false;
      ring_.push_back(c);
    }
    return true;
  }

  // Each new edge is the edge from v1 onwards of one new triangle.
  bool near_ok() {
    for (const Corners& c : ring_) {
      const std::int32_t a = c.v[0].idx(), b = c.v[1].idx(), d = c.v[2].idx();
      const Vec3 centroid = to_vec((c.p[0] + c.p[1] + c.p[2]) / 3.0);
      if (!cache_.get(a, b, d, [&] { return original_->near(centroid, {a, b, d}, tolerance_); }))
        return false;
      const int i = c.kept, j = (c.kept + 1) % 3;
      const std::int32_t u = c.v[i].idx(), w = c.v[j].idx();
      const Vec3 midpoint = to_vec(0.5 * (c.p[i] + c.p[j]));
      if (!cache_.get(u, w, -1, [&] { return original_->near(midpoint, {u, w}, tolerance_); })) return false;
    }
    return true;
  }

  void update_sine(OMesh::FaceHandle f) {
    std::array<OMesh::Point, 3> p;
    int k = 0;
    for (const OMesh::VertexHandle u : mesh().fv_range(f)) p[k++] = mesh().point(u);
    sines_[f.idx()] = min_angle_sine(p[0], p[1], p[2]);
  }

  OpenMesh::Decimater::ModQuadricT<OMesh> quadric_;
  OpenMesh::Decimater::ModHausdorffT<OMesh> hausdorff_;
  const Original* original_ = nullptr;
  double tolerance_ = 0.0;
  const double min_sine_ = std::sin(kMinAngleDegrees * std::numbers::pi / 180.0);
  const double min_cos_ = std::cos(kMaxNormalDegrees * std::numbers::pi / 180.0);
  std::vector<double> sines_;  // of the smallest angle of each triangle, kept up to date
  std::vector<Corners> ring_;  // the triangles the collapse changes, as they would be
  NearCache cache_;

  // The vertex whose collapses were rated last, after how many collapses, and the one chosen.
  OMesh::VertexHandle vertex_;
  std::size_t vertex_collapses_ = 0, collapses_ = 0;
  OMesh::HalfedgeHandle chosen_;
  float chosen_error_ = 0.0f;
  std::vector<std::pair<float, int>> candidates_;  // (quadric, halfedge)
};

void validate(const DecimateOptions& options) {
  if (options.max_triangles < 4)
    throw InputError("the triangle limit must be at least 4, the fewest a closed mesh has; got " +
                     std::to_string(options.max_triangles));
  if (!std::isfinite(options.max_distance) || options.max_distance <= 0.0)
    throw InputError(
        "the distance bound for reducing triangles must be a positive number in the mesh's units; got " +
        std::to_string(options.max_distance));
}

// Vertex i of the OpenMesh mesh is vertex i of `mesh`. The status flags, in which the decimater
// marks collapsed elements deleted, outlive the decimater.
void to_openmesh(const TriangleMesh& mesh, OMesh& om) {
  om.reserve(mesh.vertices.size(), 3 * mesh.triangles.size() / 2, mesh.triangles.size());
  for (const Vec3& p : mesh.vertices) om.add_vertex(to_point(p));
  for (const auto& t : mesh.triangles)
    if (!om.add_face(OMesh::VertexHandle(t[0]), OMesh::VertexHandle(t[1]), OMesh::VertexHandle(t[2]))
             .is_valid())
      throw std::runtime_error("mesh decimation: OpenMesh refused a triangle of the mesh");
  om.request_vertex_status();
  om.request_edge_status();
  om.request_face_status();
}

// Reports the collapses' progress and stops the decimater when the run is cancelled (an exception
// thrown through OpenMesh would leave its state to its destructors; this stops it cleanly).
class CollapseObserver : public OpenMesh::Decimater::Observer {
 public:
  CollapseObserver(const StageProgress& progress, std::size_t collapses)
      : Observer(1000), progress_(progress), collapses_(collapses) {}
  void notify(std::size_t step) override {
    if (collapses_ > 0) progress_.advance(static_cast<double>(step) / static_cast<double>(collapses_));
  }
  bool abort() const override { return progress_.cancelled(); }

 private:
  StageProgress progress_;
  std::size_t collapses_;
};

void collapse_edges(OMesh& om, std::int64_t max_triangles, const Original& original, double tolerance,
                    const StageProgress& progress) {
  OpenMesh::Decimater::DecimaterT<OMesh> decimater(om);
  ModBounded::Handle bounded;
  decimater.add(bounded);
  decimater.module(bounded).set_bounds(&original, tolerance);
  if (!decimater.initialize()) throw std::runtime_error("mesh decimation: OpenMesh decimater setup failed");
  // Each collapse removes two triangles.
  const std::size_t faces = om.n_faces(), target = static_cast<std::size_t>(max_triangles);
  CollapseObserver observer(progress, faces > target ? (faces - target) / 2 : 0);
  decimater.set_observer(&observer);
  decimater.decimate_to_faces(0, target);
  decimater.set_observer(nullptr);
  progress.check();
}

// The triangles left, in their original order, over the vertices they use, in their original order.
TriangleMesh from_openmesh(const OMesh& om, const TriangleMesh& original) {
  std::vector<std::int32_t> index(original.vertices.size(), -1);
  for (const OMesh::FaceHandle f : om.faces())  // skips deleted ones
    for (const OMesh::VertexHandle v : om.fv_range(f)) index[v.idx()] = 0;
  TriangleMesh reduced;
  for (std::size_t v = 0; v < index.size(); ++v)
    if (index[v] == 0) {
      index[v] = static_cast<std::int32_t>(reduced.vertices.size());
      reduced.vertices.push_back(original.vertices[v]);
    }
  for (const OMesh::FaceHandle f : om.faces()) {
    std::array<std::int32_t, 3> t{};
    int k = 0;
    for (const OMesh::VertexHandle v : om.fv_range(f)) t[k++] = index[v.idx()];
    reduced.triangles.push_back(t);
  }
  return reduced;
}

// Largest distance from the points to the surface. A maximum is exact in any order, so the
// parallel reduction gives the same answer on any number of threads.
double max_distance_to(const MeshSurface& surface, const std::vector<Vec3>& points) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, points.size()), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double d) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) d = std::max(d, surface.distance(points[i]));
        return d;
      },
      [](double a, double b) { return std::max(a, b); });
}

// Vertices, edge midpoints and centroids: where a flat triangle strays furthest from a curved
// surface, short of a dense sampling.
std::vector<Vec3> sample_points(const TriangleMesh& mesh) {
  std::vector<Vec3> points = mesh.vertices;
  points.reserve(points.size() + 5 * mesh.triangles.size() / 2);
  for (const auto& t : mesh.triangles) {
    points.push_back((mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0);
    for (int i = 0; i < 3; ++i)
      if (t[i] < t[(i + 1) % 3])  // each edge of a closed oriented mesh once
        points.push_back(0.5 * (mesh.vertices[t[i]] + mesh.vertices[t[(i + 1) % 3]]));
  }
  return points;
}

// Both ways: the reduced surface's sample points to the original surface, and the original
// vertices (a dense sampling of it) to the reduced surface.
double two_sided_distance(const MeshSurface& original_surface, const TriangleMesh& original,
                          const TriangleMesh& reduced) {
  const double to_original = max_distance_to(original_surface, sample_points(reduced));
  const double to_reduced = max_distance_to(MeshSurface(reduced), original.vertices);
  return std::max(to_original, to_reduced);
}

void check_result(const MeshTopology& before, const MeshTopology& after, double volume_tolerance) {
  if (const std::string problem = printability_failures(after); !problem.empty())
    throw std::runtime_error("mesh decimation produced " + problem);
  if (after.euler_characteristic != before.euler_characteristic || after.components != before.components)
    throw std::runtime_error("mesh decimation changed the topology: Euler characteristic " +
                             std::to_string(before.euler_characteristic) + " -> " +
                             std::to_string(after.euler_characteristic) + ", components " +
                             std::to_string(before.components) + " -> " + std::to_string(after.components));
  if (std::abs(after.signed_volume - before.signed_volume) > volume_tolerance)
    throw std::runtime_error("mesh decimation changed the volume from " +
                             std::to_string(before.signed_volume) + " to " +
                             std::to_string(after.signed_volume));
}

}  // namespace

DecimateResult decimate_mesh(TriangleMesh& mesh, const DecimateOptions& options) {
  validate(options);
  DecimateResult result;
  result.triangles_before = result.triangles_after = static_cast<std::int64_t>(mesh.triangles.size());
  result.reached_target = result.triangles_before <= options.max_triangles;
  if (result.reached_target) return result;

  const StageProgress& progress = options.progress;
  const MeshTopology before = analyze_topology(mesh, progress.part(0.0, 0.05));
  if (const std::string problem = printability_failures(before); !problem.empty())
    throw std::runtime_error(
        "mesh decimation needs a closed, manifold, outward oriented mesh; this one has " + problem);
  // The surfaces are at most max_distance apart, so the volume between them is at most about
  // max_distance * area.
  const double volume_tolerance = options.max_distance * surface_area(mesh);
  const MeshSurface original_surface(mesh);
  const Original original(mesh, original_surface);
  progress.advance(0.03);

  double tolerance = options.max_distance;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    // The collapses are nearly all of the time, and attempts after the first are rare: the first gets
    // the share up to 0.97, each later one half of what is left.
    const StageProgress part = progress.part(attempt == 0 ? 0.03 : 1.0 - 0.03 * std::pow(0.5, attempt - 1),
                                             1.0 - 0.03 * std::pow(0.5, attempt));
    OMesh om;
    to_openmesh(mesh, om);
    collapse_edges(om, options.max_triangles, original, tolerance, part.part(0.0, 0.95));
    TriangleMesh reduced = from_openmesh(om, mesh);
    part.advance(0.96);
    const double distance = two_sided_distance(original_surface, mesh, reduced);
    part.advance(0.99);
    if (distance > options.max_distance) {
      tolerance *= 0.9 * options.max_distance / distance;
      continue;
    }
    check_result(before, analyze_topology(reduced), volume_tolerance);
    result.triangles_after = static_cast<std::int64_t>(reduced.triangles.size());
    result.max_distance = distance;
    result.reached_target = result.triangles_after <= options.max_triangles;
    mesh = std::move(reduced);
    return result;
  }
  throw std::runtime_error("mesh decimation could not keep the reduced surface within " +
                           std::to_string(options.max_distance) + " of the original");
}

}  // namespace poreshell
