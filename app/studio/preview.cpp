#include "preview.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "poreshell/base64.hpp"

namespace studio {
namespace {

template <class T>
void append(std::string& bytes, T value) {
  char raw[sizeof value];
  std::memcpy(raw, &value, sizeof value);  // little-endian hosts only, as the page's typed arrays
  bytes.append(raw, sizeof value);
}

double mesh_area(const poreshell::Mesh& mesh) {
  double area = 0.0;
  for (const poreshell::Triangle& t : mesh.triangles) {
    const auto& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const auto& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const auto& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
  return area;
}

// The painted surface as the page draws it: float32 positions, uint32 indices, float32 pattern - level,
// and an id of its positions and indices. Where the page shows that surface already (`known_id`: most
// edits, a seed, a keep-out, the brush, the rim, leave the preview's split of the model as it was), the
// pattern alone: the bunny's preview answer falls from 4 MB to 1 MB, the page's redraw from 1.17 s
// (median of 5 seed changes, headless chromium) to the figures in docs/studio.md.
nlohmann::json surface_json(const poreshell::Output& out, const std::string& known_id) {
  std::string positions, indices, pattern;
  positions.reserve(out.mesh.vertices.size() * 12);
  for (const poreshell::Point& p : out.mesh.vertices)
    for (const double c : p) append(positions, static_cast<float>(c));
  indices.reserve(out.mesh.triangles.size() * 12);
  for (const poreshell::Triangle& t : out.mesh.triangles)
    for (const std::int32_t i : t) append(indices, static_cast<std::uint32_t>(i));
  for (const double v : out.pattern) append(pattern, static_cast<float>(v - out.iso));
  const std::size_t hash = std::hash<std::string>{}(positions) ^ (std::hash<std::string>{}(indices) << 1);
  const std::string id = std::to_string(hash) + "-" + std::to_string(out.mesh.vertices.size());
  nlohmann::json surface = {{"id", id}, {"pattern", poreshell::base64_encode(pattern)}};
  if (id != known_id) {
    surface["positions"] = poreshell::base64_encode(positions);
    surface["indices"] = poreshell::base64_encode(indices);
  }
  return surface;
}

}  // namespace

nlohmann::json model_mesh_json(const Model& model) {
  const auto* mesh = std::get_if<poreshell::MeshInput>(&model.input);
  const auto* cloud = std::get_if<poreshell::PointsInput>(&model.input);
  const double mm = poreshell::millimetres_per(model.unit);
  std::string positions, indices;
  for (const poreshell::Point& p : mesh ? mesh->mesh.vertices : cloud->points)
    for (const double c : p) append(positions, static_cast<float>(c * mm));
  for (const poreshell::Triangle& t : mesh ? mesh->mesh.triangles : cloud->patches)
    for (const std::int32_t i : t) append(indices, static_cast<std::uint32_t>(i));
  return {{"positions", poreshell::base64_encode(positions)}, {"indices", poreshell::base64_encode(indices)}};
}

nlohmann::json preview_figures(const poreshell::Result& result) {
  const poreshell::Report& r = result.report;
  const poreshell::Output& out = result.outputs.front();
  const poreshell::SpotHoleStats& s = r.outputs.front().holes;
  // The smallest ligament: the least solid between a hole and its nearest neighbour.
  double ligament = std::numeric_limits<double>::infinity();
  for (const poreshell::Hole& h : out.holes)
    if (h.nearest > 0.0) ligament = std::min(ligament, h.nearest - h.diameter);
  const double area = mesh_area(out.mesh);
  const double wall = r.solid.wall_mm > 0.0 ? r.solid.wall_mm : poreshell::kDefaultWallMm;
  const double mass_g = area * wall * (1.0 - s.porosity) * 1.24e-3;
  nlohmann::json figures = {{"holes", out.holes.size()},
                            {"diameter", s.diameter_mean},
                            {"spacing", s.spacing_mean},
                            {"porosity", s.porosity},
                            {"wall", wall},
                            {"area", area},
                            {"mass", mass_g}};
  figures["ligament"] = std::isfinite(ligament) ? nlohmann::json(ligament) : nlohmann::json(nullptr);
  return figures;
}

nlohmann::json Previews::run(const RunRequest& request) {
  auto cancel = std::make_shared<std::atomic<bool>>(false);
  {
    std::lock_guard lock(mutex_);
    if (current_) *current_ = true;  // the page wants this edit, not the previous one
    current_ = cancel;
    if (stopped_) *cancel = true;
  }
  poreshell::Options options = request.options;
  options.preview = true;
  const poreshell::Input input = masked_input(request.model->input, request.mask, options);
  poreshell::RunControl control;
  control.cancel = cancel.get();
  const auto start = std::chrono::steady_clock::now();
  const poreshell::Result result = poreshell::perforate(input, options, control);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const poreshell::Output& out = result.outputs.front();
  nlohmann::json centres = nlohmann::json::array(), diameters = nlohmann::json::array();
  for (const poreshell::Hole& h : out.holes) {
    centres.push_back({h.centre[0], h.centre[1], h.centre[2]});
    diameters.push_back(h.diameter);
  }
  return {{"holes", out.holes.size()},
          {"centres", std::move(centres)},
          {"diameters", std::move(diameters)},
          {"figures", preview_figures(result)},
          {"surface", surface_json(out, request.surface_id)},
          {"warnings", result.report.warnings},
          {"seconds", seconds},
          {"model", request.model->id}};
}

void Previews::stop() {
  std::lock_guard lock(mutex_);
  stopped_ = true;
  if (current_) *current_ = true;
}

}  // namespace studio
