#include "io/stl.hpp"

// Binary STL: 80-byte header, uint32 triangle count, then per triangle a float32 normal, three
// float32 vertices and a uint16 attribute, all little-endian. Bytes are assembled explicitly so
// the format does not depend on the host's byte order.

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace poreshell {
namespace {

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kFacetBytes = 50;

void put_u32(char* out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out[b] = static_cast<char>((v >> (8 * b)) & 0xFFu);
}

std::uint32_t get_u32(const unsigned char* in) {
  std::uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = (v << 8) | in[b];
  return v;
}

void put_f32(char* out, double v) {
  put_u32(out, std::bit_cast<std::uint32_t>(static_cast<float>(v)));
}

float get_f32(const unsigned char* in) {
  return std::bit_cast<float>(get_u32(in));
}

}  // namespace

void write_stl_binary(const std::filesystem::path& path, const TriangleMesh& mesh) {
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    throw InputError("the mesh has too many triangles for binary STL; lower the resolution");
  write_atomically(path, [&](std::ostream& out) {
    char header[kHeaderBytes] = {};
    const std::string title = "poreshell porous shell, binary STL";
    std::copy(title.begin(), title.end(), header);
    out.write(header, kHeaderBytes);
    char count[4];
    put_u32(count, static_cast<std::uint32_t>(mesh.triangles.size()));
    out.write(count, 4);

    // Facets are encoded in parallel, a chunk at a time, and written in large blocks rather than one
    // 50-byte stream write each (24 M facets at 830 points).
    constexpr std::size_t kChunk = std::size_t{1} << 18;  // 13 MB of facets
    const std::size_t total = mesh.triangles.size();
    std::vector<char> buffer(std::min(total, kChunk) * kFacetBytes, 0);  // attribute bytes stay 0
    for (std::size_t first = 0; first < total; first += kChunk) {
      const std::size_t in_chunk = std::min(kChunk, total - first);
      tbb::parallel_for(std::size_t{0}, in_chunk, [&](std::size_t f) {
        const auto& t = mesh.triangles[first + f];
        const Vec3& a = mesh.vertices.at(t[0]);
        const Vec3& b = mesh.vertices.at(t[1]);
        const Vec3& c = mesh.vertices.at(t[2]);
        Vec3 n = (b - a).cross(c - a);
        const double len = n.norm();
        n = len > 0.0 ? Vec3(n / len) : Vec3::Zero();  // readers recompute normals; zero is allowed
        const Vec3* corners[4] = {&n, &a, &b, &c};
        char* facet = buffer.data() + kFacetBytes * f;
        for (int v = 0; v < 4; ++v)
          for (int d = 0; d < 3; ++d) put_f32(&facet[12 * v + 4 * d], (*corners[v])[d]);
      });
      out.write(buffer.data(), static_cast<std::streamsize>(in_chunk * kFacetBytes));
    }
  });
}

TriangleMesh read_stl_binary(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open STL file '" + path.string() + "'; check the path");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  if (bytes.size() < kHeaderBytes + 4)
    throw InputError("'" + path.string() + "' is too short to be a binary STL file");
  const std::uint32_t count = get_u32(&bytes[kHeaderBytes]);
  const std::size_t expected = kHeaderBytes + 4 + kFacetBytes * std::size_t{count};
  if (bytes.size() < expected)
    throw InputError("'" + path.string() + "' is truncated: it declares " + std::to_string(count) +
                     " triangles but holds only " + std::to_string(bytes.size()) + " bytes");

  // Weld by sorting the 3 * count corners on their exact coordinates.
  struct Corner {
    std::array<float, 3> p;
    std::size_t slot;  // 3 * triangle + corner
  };
  if (3 * std::size_t{count} > std::size_t{std::numeric_limits<std::int32_t>::max()})
    throw InputError("'" + path.string() + "' has too many triangles to load");
  std::vector<Corner> corners(3 * std::size_t{count});
  for (std::size_t f = 0; f < count; ++f) {
    const unsigned char* facet = &bytes[kHeaderBytes + 4 + kFacetBytes * f];
    for (std::size_t c = 0; c < 3; ++c) {
      Corner& corner = corners[3 * f + c];
      for (std::size_t d = 0; d < 3; ++d) {
        corner.p[d] = get_f32(facet + 12 * (c + 1) + 4 * d);
        if (!std::isfinite(corner.p[d]))
          throw InputError("'" + path.string() + "' has a non-finite coordinate in triangle " +
                           std::to_string(f));
      }
      corner.slot = 3 * f + c;
    }
  }
  std::sort(corners.begin(), corners.end(),
            [](const Corner& x, const Corner& y) { return x.p != y.p ? x.p < y.p : x.slot < y.slot; });

  TriangleMesh mesh;
  mesh.triangles.resize(count);
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (i == 0 || corners[i].p != corners[i - 1].p)
      mesh.vertices.emplace_back(corners[i].p[0], corners[i].p[1], corners[i].p[2]);
    mesh.triangles[corners[i].slot / 3][corners[i].slot % 3] =
        static_cast<std::int32_t>(mesh.vertices.size() - 1);
  }
  return mesh;
}

}  // namespace poreshell
