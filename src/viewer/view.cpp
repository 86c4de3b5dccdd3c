// The public API's viewer (include/poreshell/viewer.hpp): the result in the viewer's terms.

#include <span>
#include <string>
#include <variant>

#include "core/error.hpp"
#include "input/placement.hpp"
#include "io/file_format.hpp"
#include "io/report_json.hpp"
#include "pattern/solid_zones.hpp"
#include "poreshell/io.hpp"
#include "poreshell/viewer.hpp"
#include "viewer/display_mesh.hpp"
#include "viewer/html_viewer.hpp"

namespace poreshell {
namespace {

// The open boundary of a mesh input, in mm, as two-point lines.
std::vector<std::vector<Vec3>> boundary_lines(const Input* input) {
  const auto* mesh = input ? std::get_if<MeshInput>(input) : nullptr;
  if (!mesh) return {};
  const double mm = millimetres_per(mesh->unit);
  std::vector<std::vector<Vec3>> lines;
  for (const Segment& s : boundary_segments(to_triangle_mesh(mesh->mesh)))
    lines.push_back({s[0] * mm, s[1] * mm});
  return lines;
}

// ViewOptions::up as the viewer's axis index (0 x, 1 y, 2 z).
int up_axis(char up, const Input* input) {
  if (up == 'x' || up == 'y' || up == 'z') return up - 'x';
  if (up != 0) throw Error(ErrorCode::invalid_option, "the up axis must be x, y or z", "up");
  std::string name;
  if (const auto* mesh = input ? std::get_if<MeshInput>(input) : nullptr) name = mesh->name;
  if (const auto* points = input ? std::get_if<PointsInput>(input) : nullptr) name = points->name;
  const std::string extension = lowercase_extension(name);
  return extension == ".obj" || extension == ".ply" ? 1 : 2;
}

TriangleMesh as_is(const Mesh& mesh) {
  TriangleMesh out;
  out.vertices.reserve(mesh.vertices.size());
  for (const Point& p : mesh.vertices) out.vertices.push_back(vec(p));
  out.triangles.assign(mesh.triangles.begin(), mesh.triangles.end());
  return out;
}

// A preview's pattern (minus the pore level) on the shown mesh: a reduced mesh's vertex, the mean of
// the vertices clustered into it, takes the mean of their values (no search: the clustering says which).
std::vector<float> display_pattern(std::span<const double> pattern, std::span<const std::int32_t> shown_as,
                                   std::size_t shown_vertices, double iso) {
  if (pattern.size() != shown_as.size())
    throw Error(ErrorCode::invalid_option, "the output's pattern does not match its mesh", "pattern");
  std::vector<double> sum(shown_vertices, 0.0);
  std::vector<int> count(shown_vertices, 0);
  for (std::size_t v = 0; v < pattern.size(); ++v) {
    sum[static_cast<std::size_t>(shown_as[v])] += pattern[v];
    ++count[static_cast<std::size_t>(shown_as[v])];
  }
  std::vector<float> values(shown_vertices);
  for (std::size_t c = 0; c < shown_vertices; ++c) values[c] = static_cast<float>(sum[c] / count[c] - iso);
  return values;
}

}  // namespace

void save_html(const std::filesystem::path& path, const Result& result, const Options& options,
               const Input* input, const ViewOptions& view) {
  check_output_path(path);
  if (view.output >= result.outputs.size())
    throw Error(ErrorCode::invalid_option, "the result has no output " + std::to_string(view.output),
                "output");
  const Output& out = result.outputs[view.output];
  ViewerData data;
  data.title = view.title.empty() ? result.report.input.name : view.title;
  // A preview's mesh as it is (its pattern is per vertex); any other cleaned as an input would be.
  const TriangleMesh mesh = out.pattern.empty() ? to_triangle_mesh(out.mesh) : as_is(out.mesh);
  std::vector<std::int32_t> shown_as;
  data.mesh = reduce_for_display(mesh, view.max_triangles, &shown_as);
  if (!out.pattern.empty())
    data.pattern = display_pattern(out.pattern, shown_as, data.mesh.vertices.size(), out.iso);
  for (const Hole& h : out.holes)
    data.holes.push_back(
        {vec(h.centre), vec(h.normal), h.diameter, h.circularity, h.nearest, h.axis_ratio, h.asked_diameter});
  if (result.report.plan) data.requested_diameter_mm = result.report.plan->diameter;
  // The rim the run applied (a default one is half a hole).
  data.rim_width_mm = result.report.outputs.empty() ? 0.0 : result.report.outputs.front().zones.rim_asked;
  if (data.rim_width_mm > 0.0) data.rim_loops = boundary_lines(input);
  for (const KeepOutSphere& k : options.keep_out) data.keep_out_spheres.push_back({vec(k.centre), k.radius});
  for (const KeepOutBox& k : options.keep_out_boxes) data.keep_out_boxes.push_back({vec(k.min), vec(k.max)});
  data.report = to_json(result.report, result.outputs);
  data.density_g_per_cm3 = view.density_g_per_cm3;
  data.up_axis = up_axis(view.up, input);
  write_html_viewer(path, data);
}

void save_png(const std::filesystem::path& html, const std::filesystem::path& png) {
  check_output_path(png);
  render_html_png(html, png);
}

}  // namespace poreshell
