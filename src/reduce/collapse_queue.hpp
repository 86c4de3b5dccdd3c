#pragma once
// What the edge collapses (edge_collapse.hpp) order their work by: error quadrics, and a queue of
// vertices by error.

#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/mesh.hpp"

namespace poreshell {

// Sum of squared distances to planes, each weighted by its triangle's area: the symmetric 4 x 4
// matrix's upper triangle.
struct Quadric {
  double xx = 0, xy = 0, xz = 0, xw = 0, yy = 0, yz = 0, yw = 0, zz = 0, zw = 0, ww = 0;

  static Quadric plane(const Vec3& n, double d, double weight) {
    return {weight * n.x() * n.x(), weight * n.x() * n.y(), weight * n.x() * n.z(), weight * n.x() * d,
            weight * n.y() * n.y(), weight * n.y() * n.z(), weight * n.y() * d,     weight * n.z() * n.z(),
            weight * n.z() * d,     weight * d * d};
  }
  Quadric& operator+=(const Quadric& o) {
    xx += o.xx, xy += o.xy, xz += o.xz, xw += o.xw, yy += o.yy;
    yz += o.yz, yw += o.yw, zz += o.zz, zw += o.zw, ww += o.ww;
    return *this;
  }
  // The sum of squared distances at p.
  double at(const Vec3& p) const {
    const double x = p.x(), y = p.y(), z = p.z();
    return x * (xx * x + 2.0 * (xy * y + xz * z + xw)) + y * (yy * y + 2.0 * (yz * z + yw)) +
           z * (zz * z + 2.0 * zw) + ww;
  }
};

// Each vertex's quadric: the planes of its triangles, each weighted by the triangle's area. The sums
// run in triangle order, so that they are the same on any thread count.
inline std::vector<Quadric> vertex_quadrics(const TriangleMesh& mesh) {
  std::vector<Quadric> quadric(mesh.vertices.size());
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    const double twice_area = n.norm();
    const Vec3 unit = twice_area > 0.0 ? Vec3(n / twice_area) : Vec3::Zero();
    const Quadric q = Quadric::plane(unit, -unit.dot(a), 0.5 * twice_area);
    for (int k = 0; k < 3; ++k) quadric[static_cast<std::size_t>(t[k])] += q;
  }
  return quadric;
}

// The vertices waiting to collapse, least key first. Keys are errors rounded down to four octaves
// (every fourth exponent of a non-negative double), ties by vertex: collapses within a factor of 16 of
// each other go in vertex order, so that those in one part of the mesh go one after another, while its
// data is in the cache. On the bunny's 1.5 M triangles, keys of half an octave took bench_reduce from
// 9.7-10.3 s (exact errors) to 7.7 s; four octaves then took it from 5.4-6.0 s to 4.8-5.4 s (runs in
// turn), at the same deviation, triangle count and smallest angle, with 8 % more triangles with an
// angle under 10 degrees (docs/benchmarks.md "The reduction's loop"). With so few distinct keys, each
// is a set of vertices as a bitmap with two levels of summary words: the least vertex of the least key
// is three word scans away, and a vertex goes in or out by setting a few bits, where a binary heap
// moved it through some twenty levels.
// KeyShift sets the rounding: 54 keeps the top 10 bits (four octaves a key), 52 one octave.
template <int KeyShift = 54>
class VertexQueue {
 public:
  explicit VertexQueue(std::size_t vertices) : key_of_(vertices, kNone), words_((vertices + 63) / 64) {}

  bool empty() const { return size_ == 0; }
  std::int32_t top() const {
    std::size_t k = 0;
    while (occupied_[k] == 0) ++k;
    const Bits& b = *keys_[64 * k + static_cast<std::size_t>(std::countr_zero(occupied_[k]))];
    std::size_t i = 0;
    while (b.top[i] == 0) ++i;
    const std::size_t j = 64 * i + static_cast<std::size_t>(std::countr_zero(b.top[i]));
    const std::size_t w = 64 * j + static_cast<std::size_t>(std::countr_zero(b.middle[j]));
    return static_cast<std::int32_t>(64 * w + static_cast<std::size_t>(std::countr_zero(b.bottom[w])));
  }
  std::vector<std::int32_t> vertices() const {
    std::vector<std::int32_t> out;
    for (std::size_t v = 0; v < key_of_.size(); ++v)
      if (key_of_[v] != kNone) out.push_back(static_cast<std::int32_t>(v));
    return out;
  }

  void set(std::int32_t v, double error) {
    const auto key = static_cast<std::uint16_t>(std::bit_cast<std::uint64_t>(error) >> KeyShift);
    const auto u = static_cast<std::size_t>(v);
    if (key_of_[u] == key) return;
    remove(v);
    key_of_[u] = key;
    if (!keys_[key]) keys_[key] = std::make_unique<Bits>(words_);
    Bits& b = *keys_[key];
    if (b.count++ == 0) occupied_[key / 64] |= std::uint64_t{1} << (key % 64);
    b.bottom[u / 64] |= std::uint64_t{1} << (u % 64);
    b.middle[u / 4096] |= std::uint64_t{1} << (u / 64 % 64);
    b.top[u / 262144] |= std::uint64_t{1} << (u / 4096 % 64);
    ++size_;
  }
  void remove(std::int32_t v) {
    const auto u = static_cast<std::size_t>(v);
    const std::uint16_t key = key_of_[u];
    if (key == kNone) return;
    key_of_[u] = kNone;
    --size_;
    Bits& b = *keys_[key];
    if (--b.count == 0) occupied_[key / 64] &= ~(std::uint64_t{1} << (key % 64));
    if ((b.bottom[u / 64] &= ~(std::uint64_t{1} << (u % 64))) != 0) return;
    if ((b.middle[u / 4096] &= ~(std::uint64_t{1} << (u / 64 % 64))) != 0) return;
    b.top[u / 262144] &= ~(std::uint64_t{1} << (u / 4096 % 64));
  }

 private:
  static constexpr std::uint16_t kNone = 0xffff;
  static constexpr std::size_t kKeys = std::size_t{1} << (63 - KeyShift);  // a non-negative double: sign 0
  struct Bits {
    explicit Bits(std::size_t words)
        : bottom(words, 0), middle((words + 63) / 64, 0), top((words + 4095) / 4096, 0) {}
    std::vector<std::uint64_t> bottom, middle, top;  // a vertex; a word of bottom; a word of middle
    std::size_t count = 0;
  };
  std::vector<std::uint16_t> key_of_;  // per vertex, kNone where out
  std::size_t words_;
  std::array<std::unique_ptr<Bits>, kKeys> keys_{};
  std::array<std::uint64_t, kKeys / 64> occupied_{};
  std::size_t size_ = 0;
};

}  // namespace poreshell
