#include "io/mesh_io.hpp"

// STL, OBJ, OFF and PLY are read by poreshell's own small readers (mesh_readers.hpp, ply_reader.hpp):
// Assimp's importers aborted on ai_assert, crashed or ran for seconds on small crafted files
// (docs/reliability.md). 3MF goes through lib3mf, the format's reference implementation (components,
// build-item transforms). All only fill a TriangleMesh; checks and clean-up happen afterwards in one
// place, clean_triangle_mesh (geometry/mesh_clean.hpp).

#include <fmt/format.h>

#include <Eigen/Geometry>  // Affine3d
#include <memory>
#include <string>

#include "core/error.hpp"
#include "geometry/mesh_clean.hpp"
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

}  // namespace

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
