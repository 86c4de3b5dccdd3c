#include "io/mesh_io.hpp"

// STL, OBJ, OFF and PLY are read by poreshell's own small readers (mesh_readers.hpp, ply_reader.hpp):
// Assimp's importers aborted on ai_assert, crashed or ran for seconds on small crafted files
// (docs/reliability.md). 3MF goes through lib3mf, the format's reference implementation (components,
// build-item transforms). All only fill a TriangleMesh; checks and clean-up happen afterwards in one
// place, clean_triangle_mesh.

#include <fmt/format.h>

#include <Eigen/Geometry>  // Affine3d
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <tuple>

#include "core/error.hpp"
#include "io/file_bytes.hpp"
#include "io/file_format.hpp"
#include "io/lib3mf_support.hpp"
#include "io/mesh_readers.hpp"
#include "io/ply_reader.hpp"
#include "io/text_scan.hpp"

namespace poreshell {
namespace {

constexpr const char* kSupported = ".stl, .obj, .ply, .off, .3mf";

void append_triangle(TriangleMesh& out, std::size_t a, std::size_t b, std::size_t c) {
  out.triangles.push_back(
      {static_cast<std::int32_t>(a), static_cast<std::int32_t>(b), static_cast<std::int32_t>(c)});
}

void check_index_range(std::size_t vertices) {
  if (vertices > static_cast<std::size_t>(INT32_MAX))
    throw InputError("the mesh has more than 2^31 vertices: split or decimate it");
}

class Lib3mfReader {
 public:
  Lib3mfReader(std::string_view bytes, std::string name)
      : bytes_(bytes.begin(), bytes.end()), path_(std::move(name)) {}

  TriangleMesh read() {
    NMR::PLib3MFModel* model = nullptr;
    check(NMR::lib3mf_createmodel(&model), nullptr);
    const Lib3mfHandle model_handle(model);
    NMR::PLib3MFModelReader* reader = nullptr;
    check(NMR::lib3mf_model_queryreader(model, "3mf", &reader), model);
    const Lib3mfHandle reader_handle(reader);
    check(NMR::lib3mf_reader_readfrombuffer(reader, bytes_.data(), bytes_.size()), reader);

    NMR::PLib3MFModelBuildItemIterator* items = nullptr;
    check(NMR::lib3mf_model_getbuilditems(model, &items), model);
    const Lib3mfHandle items_handle(items);
    TriangleMesh out;
    for (;;) {
      BOOL has_next = 0;
      check(NMR::lib3mf_builditemiterator_movenext(items, &has_next), items);
      if (!has_next) break;
      NMR::PLib3MFModelBuildItem* item = nullptr;
      check(NMR::lib3mf_builditemiterator_getcurrent(items, &item), items);
      const Lib3mfHandle item_handle(item);
      NMR::PLib3MFModelObjectResource* object = nullptr;
      check(NMR::lib3mf_builditem_getobjectresource(item, &object), item);
      const Lib3mfHandle object_handle(object);
      const Eigen::Affine3d transform = read_transform(item, NMR::lib3mf_builditem_hasobjecttransform,
                                                       NMR::lib3mf_builditem_getobjecttransform);
      append_object(object, transform, out, 0);
    }
    return out;
  }

 private:
  // MODELTRANSFORM holds the 3x4 matrix [linear | translation] row by row.
  static Eigen::Affine3d to_affine(const NMR::MODELTRANSFORM& t) {
    Eigen::Affine3d a = Eigen::Affine3d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) a.matrix()(r, c) = t.m_fFields[r][c];
    return a;
  }

  // Build items and components store their optional transform alike, behind different functions.
  template <class Owner, class HasTransform, class GetTransform>
  Eigen::Affine3d read_transform(Owner* owner, HasTransform has_transform, GetTransform get_transform) {
    BOOL has = 0;
    check(has_transform(owner, &has), owner);
    if (!has) return Eigen::Affine3d::Identity();
    NMR::MODELTRANSFORM t;
    check(get_transform(owner, &t), owner);
    return to_affine(t);
  }

  void append_object(NMR::PLib3MFModelObjectResource* object, const Eigen::Affine3d& transform,
                     TriangleMesh& out, int depth) {
    if (depth > 32) throw InputError(fmt::format("3MF file '{}': components nest too deeply", path_));
    BOOL is_mesh = 0, is_components = 0;
    check(NMR::lib3mf_object_ismeshobject(object, &is_mesh), object);
    check(NMR::lib3mf_object_iscomponentsobject(object, &is_components), object);
    if (is_mesh) {
      DWORD nv = 0, nt = 0;
      check(NMR::lib3mf_meshobject_getvertexcount(object, &nv), object);
      check(NMR::lib3mf_meshobject_gettrianglecount(object, &nt), object);
      std::vector<NMR::MODELMESHVERTEX> vertices(nv);
      std::vector<NMR::MODELMESHTRIANGLE> triangles(nt);
      if (nv > 0) check(NMR::lib3mf_meshobject_getvertices(object, vertices.data(), nv, nullptr), object);
      if (nt > 0)
        check(NMR::lib3mf_meshobject_gettriangleindices(object, triangles.data(), nt, nullptr), object);
      const std::size_t base = out.vertices.size();
      check_index_range(base + nv);
      for (const auto& v : vertices)
        out.vertices.push_back(transform * Vec3(v.m_fPosition[0], v.m_fPosition[1], v.m_fPosition[2]));
      for (const auto& t : triangles)
        append_triangle(out, base + t.m_nIndices[0], base + t.m_nIndices[1], base + t.m_nIndices[2]);
    }
    if (is_components) {
      DWORD count = 0;
      check(NMR::lib3mf_componentsobject_getcomponentcount(object, &count), object);
      for (DWORD i = 0; i < count; ++i) {
        NMR::PLib3MFModelComponent* component = nullptr;
        check(NMR::lib3mf_componentsobject_getcomponent(object, i, &component), object);
        const Lib3mfHandle component_handle(component);
        NMR::PLib3MFModelObjectResource* child = nullptr;
        check(NMR::lib3mf_component_getobjectresource(component, &child), component);
        const Lib3mfHandle child_handle(child);
        const Eigen::Affine3d local =
            read_transform(component, NMR::lib3mf_component_hastransform, NMR::lib3mf_component_gettransform);
        append_object(child, transform * local, out, depth + 1);
      }
    }
  }

  void check(LIB3MFRESULT result, NMR::PLib3MFBase* handle) const {
    if (result == LIB3MF_OK) return;
    const std::string message = lib3mf_error_text(result, handle);
    throw InputError(fmt::format(
        "cannot read mesh file '{}': {}; check that it is a complete, valid .3mf file", path_, message));
  }

  std::vector<BYTE> bytes_;  // a copy: lib3mf's buffer reader takes a non-const pointer
  std::string path_;
};

void check_extension(const std::string& extension, const std::string& name) {
  if (extension != ".stl" && extension != ".obj" && extension != ".ply" && extension != ".off" &&
      extension != ".3mf")
    throw InputError(fmt::format("mesh file '{}' has the unsupported extension '{}': use one of {}", name,
                                 text::quote(extension), kSupported));
}

TriangleMesh from_ply(std::string_view bytes, const std::string& name) {
  ply::Data data = ply::read(bytes, name);
  return TriangleMesh{std::move(data.vertices), std::move(data.triangles)};
}

// A triangle's area counts as zero below 1e-14 of its longest edge squared, so a vertex placed absurdly
// far from the rest (1e16 mm from a 20 mm cube, or a float's 3.4e38) makes needles of all its triangles:
// dropping them would open a closed part with no word and hide the vertex from the size check (issue
// 47). Such a vertex, used by no kept triangle and outside the kept part's box by more than its
// diagonal, is refused by its index.
void refuse_far_thin_corners(const std::vector<Vec3>& vertices, const std::vector<std::int32_t>& imported,
                             const std::vector<std::array<std::int32_t, 3>>& kept,
                             const std::vector<std::int32_t>& thin_corners) {
  if (thin_corners.empty()) return;
  std::vector<char> in_kept(vertices.size(), 0);
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const auto& t : kept)
    for (const std::int32_t v : t) {
      in_kept[v] = 1;
      low = low.cwiseMin(vertices[v]);
      high = high.cwiseMax(vertices[v]);
    }
  const double reach = (high - low).norm();
  for (const std::int32_t v : thin_corners) {
    if (in_kept[v]) continue;
    const Vec3& p = vertices[v];
    const double outside = ((low - p).cwiseMax(0.0) + (p - high).cwiseMax(0.0)).maxCoeff();
    if (outside > reach)
      throw InputError(fmt::format(
          "vertex {} (counting from 0, as imported) at ({:.4g}, {:.4g}, {:.4g}) lies far outside the rest of "
          "the mesh (which spans ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g})), and its triangles "
          "are "
          "too thin to keep at that scale, so the part would lose them; remove or fix the vertex, or "
          "re-export the mesh",
          imported[v], p.x(), p.y(), p.z(), low.x(), low.y(), low.z(), high.x(), high.y(), high.z()));
  }
}

// Drops each triangle whose three vertices an earlier one has (either orientation), keeping the first;
// returns how many. A polygon fanned over a few coincident corners (a 4,000-vertex OBJ face over a cube's
// 8 corners) or an object placed many times at one spot gives thousands of coincident triangles that
// add nothing but make every later search slow (issue 47: 23 s for 4,000, a hang for 100,000).
std::int64_t drop_repeated_triangles(std::vector<std::array<std::int32_t, 3>>& triangles) {
  std::vector<std::array<std::int32_t, 4>> keys(triangles.size());  // sorted corners, then the index
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    std::array<std::int32_t, 3> c = triangles[t];
    std::sort(c.begin(), c.end());
    keys[t] = {c[0], c[1], c[2], static_cast<std::int32_t>(t)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<char> repeat(triangles.size(), 0);
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i][0] == keys[i - 1][0] && keys[i][1] == keys[i - 1][1] && keys[i][2] == keys[i - 1][2])
      repeat[static_cast<std::size_t>(keys[i][3])] = 1;
  std::size_t kept = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (!repeat[t]) triangles[kept++] = triangles[t];
  const auto dropped = static_cast<std::int64_t>(triangles.size() - kept);
  triangles.resize(kept);
  return dropped;
}

}  // namespace

MeshInputStats clean_triangle_mesh(TriangleMesh& mesh) {
  const std::size_t nv = mesh.vertices.size();
  std::vector<char> used(nv, 0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (std::int32_t v : mesh.triangles[f]) {
      if (v < 0 || static_cast<std::size_t>(v) >= nv)
        throw InputError(
            fmt::format("triangle {} refers to vertex {}, but the mesh has {} vertices", f, v, nv));
      used[v] = 1;
    }
  std::vector<std::int32_t> order;
  for (std::size_t v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    const Vec3& p = mesh.vertices[v];
    if (!p.allFinite())
      throw InputError(
          fmt::format("vertex {} (counting from 0, as imported) has a non-finite coordinate ({}, {}, {}) "
                      "(NaN or infinity): the file is corrupt; "
                      "repair or re-export the mesh",
                      v, p.x(), p.y(), p.z()));
    order.push_back(static_cast<std::int32_t>(v));
  }

  // Exact weld: sorting by position puts identical vertices next to each other.
  const auto less = [&](std::int32_t a, std::int32_t b) {
    const Vec3 &p = mesh.vertices[a], &q = mesh.vertices[b];
    return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
  };
  std::stable_sort(order.begin(), order.end(), less);
  std::vector<std::int32_t> remap(nv, -1), imported;  // imported: a welded vertex's first index as read
  std::vector<Vec3> vertices;
  vertices.reserve(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || less(order[i - 1], order[i])) {
      vertices.push_back(mesh.vertices[order[i]]);
      imported.push_back(order[i]);
    }
    remap[order[i]] = static_cast<std::int32_t>(vertices.size() - 1);
  }

  MeshInputStats stats;
  std::vector<std::array<std::int32_t, 3>> triangles;
  triangles.reserve(mesh.triangles.size());
  std::vector<std::int32_t> thin_corners;  // corners of triangles dropped for their zero area
  for (const auto& t : mesh.triangles) {
    const std::array<std::int32_t, 3> r{remap[t[0]], remap[t[1]], remap[t[2]]};
    if (has_repeated_vertex(r) || zero_area(vertices[r[0]], vertices[r[1]], vertices[r[2]])) {
      if (!has_repeated_vertex(r)) thin_corners.insert(thin_corners.end(), r.begin(), r.end());
      ++stats.dropped_degenerate;
      continue;
    }
    triangles.push_back(r);
  }
  if (triangles.empty())
    throw InputError(
        fmt::format("the mesh has no usable triangles: all {} repeat a vertex or have zero area (collinear "
                    "corners); give a "
                    "mesh whose faces enclose some area",
                    stats.dropped_degenerate));
  refuse_far_thin_corners(vertices, imported, triangles, thin_corners);
  stats.dropped_duplicate = drop_repeated_triangles(triangles);
  // Drop vertices that only dropped triangles used.
  std::vector<std::int32_t> compact(vertices.size(), -1);
  mesh.vertices.clear();
  for (auto& t : triangles)
    for (std::int32_t& v : t) {
      if (compact[v] < 0) {
        compact[v] = static_cast<std::int32_t>(mesh.vertices.size());
        mesh.vertices.push_back(vertices[v]);
      }
      v = compact[v];
    }
  mesh.triangles = std::move(triangles);
  stats.vertices = static_cast<std::int64_t>(mesh.vertices.size());
  stats.triangles = static_cast<std::int64_t>(mesh.triangles.size());
  stats.boundary_edges = analyze_topology(mesh).boundary_edges;
  return stats;
}

TriangleMesh read_triangle_mesh_bytes(std::string_view bytes, const std::string& extension,
                                      const std::string& name, MeshInputStats* stats) {
  check_extension(extension, name);
  if (bytes.empty())
    throw InputError(
        fmt::format("mesh file '{}' is empty (0 bytes): give a complete {} file", name, extension));
  TriangleMesh mesh;
  if (extension == ".stl")
    mesh = read_stl_bytes(bytes, name);
  else if (extension == ".obj")
    mesh = read_obj_bytes(bytes, name);
  else if (extension == ".off")
    mesh = read_off_bytes(bytes, name);
  else if (extension == ".ply")
    mesh = from_ply(bytes, name);
  else
    mesh = Lib3mfReader(bytes, name).read();
  if (mesh.triangles.empty())
    throw InputError(fmt::format(
        "mesh file '{}' contains no triangles: give a surface mesh (a point cloud goes to --points)", name));
  try {
    const MeshInputStats s = clean_triangle_mesh(mesh);
    if (stats != nullptr) *stats = s;
  } catch (const InputError& e) {
    throw InputError(fmt::format("mesh file '{}': {}", name, e.what()));
  }
  return mesh;
}

TriangleMesh read_triangle_mesh(const std::filesystem::path& path, MeshInputStats* stats) {
  const std::string ext = lowercase_extension(path);
  check_extension(ext, path.string());  // before a large file of an unknown format is read
  return read_triangle_mesh_bytes(read_file_bytes(path, "mesh"), ext, path.string(), stats);
}

}  // namespace poreshell
