#include "models.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <stdexcept>
#include <system_error>

namespace studio {

namespace fs = std::filesystem;

std::string model_extension(std::string_view name) {
  const std::size_t dot = name.rfind('.');
  if (dot == std::string_view::npos) return {};
  std::string ext(name.substr(dot));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static constexpr std::array<std::string_view, 8> known{".stl", ".obj", ".ply", ".off",
                                                         ".3mf", ".xyz", ".txt", ".pts"};
  return std::find(known.begin(), known.end(), ext) != known.end() ? ext : std::string{};
}

poreshell::Unit parse_unit(std::string_view text) {
  if (text.empty()) return poreshell::Unit::mm;
  if (const std::optional<poreshell::Unit> unit = poreshell::unit_from_name(text)) return *unit;
  throw std::invalid_argument("units '" + std::string(text) + "' is not one of m, cm, mm, inch");
}

namespace {

// A mesh, or points for .xyz/.txt/.pts and a face-less .ply, by the loaders given (from a file or from
// bytes), named `name`.
template <class LoadMesh, class LoadPoints>
poreshell::Input read_model_by(const std::string& ext, const std::string& name, LoadMesh load_mesh,
                               LoadPoints load_points) {
  const auto as_points = [&] {
    poreshell::PointsInput points = load_points();
    points.name = name;
    return poreshell::Input(std::move(points));
  };
  if (ext == ".xyz" || ext == ".txt" || ext == ".pts") return as_points();
  poreshell::MeshInput mesh;
  try {
    mesh = load_mesh();
  } catch (const poreshell::Error&) {
    if (ext != ".ply") throw;
    return as_points();  // a PLY of vertices alone is a point cloud
  }
  mesh.name = name;
  return mesh;
}

}  // namespace

poreshell::Input read_model(const fs::path& path, poreshell::Unit unit, const std::string& name) {
  return read_model_by(
      path.extension().string(), name, [&] { return poreshell::load_mesh(path, unit); },
      [&] { return poreshell::load_points(path, unit); });
}

poreshell::Input read_model_bytes(std::string_view bytes, const std::string& name, poreshell::Unit unit) {
  return read_model_by(
      model_extension(name), name, [&] { return poreshell::load_mesh_bytes(bytes, name, unit); },
      [&] { return poreshell::load_points_bytes(bytes, name, unit); });
}

fs::path Models::new_path(const std::string& extension) {
  std::lock_guard lock(mutex_);
  return folder_ / ("model-" + std::to_string(next_file_++) + extension);
}

std::shared_ptr<const Model> Models::add(const fs::path& path, const std::string& name,
                                         poreshell::Unit unit) {
  auto model = std::make_shared<Model>();
  model->name = name;
  model->unit = unit;
  model->path = path;
  try {
    model->input = read_model(path, unit, name);
  } catch (...) {
    std::error_code ignored;
    fs::remove(path, ignored);
    throw;
  }
  const auto* mesh = std::get_if<poreshell::MeshInput>(&model->input);
  const auto* cloud = std::get_if<poreshell::PointsInput>(&model->input);
  const std::vector<poreshell::Point>& points = mesh ? mesh->mesh.vertices : cloud->points;
  model->vertices = points.size();
  model->triangles = mesh ? mesh->mesh.triangles.size() : cloud->patches.size();
  const double mm = poreshell::millimetres_per(unit);
  model->min = {1e300, 1e300, 1e300};
  model->max = {-1e300, -1e300, -1e300};
  for (const poreshell::Point& p : points)
    for (int i = 0; i < 3; ++i) {
      model->min[i] = std::min(model->min[i], p[i] * mm);
      model->max[i] = std::max(model->max[i], p[i] * mm);
    }
  std::lock_guard lock(mutex_);
  model->id = next_id_++;
  models_[model->id] = model;
  while (models_.size() > kKept) {
    std::error_code ignored;
    fs::remove(models_.begin()->second->path, ignored);
    models_.erase(models_.begin());
  }
  return model;
}

std::shared_ptr<const Model> Models::get(int id) const {
  std::lock_guard lock(mutex_);
  if (models_.empty()) return nullptr;
  if (id == 0) return models_.rbegin()->second;
  const auto it = models_.find(id);
  return it == models_.end() ? nullptr : it->second;
}

}  // namespace studio
