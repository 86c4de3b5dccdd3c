// The public API's files (include/poreshell/io.hpp): the readers and writers of io/, in public types.

#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/error.hpp"
#include "input/placement.hpp"
#include "input/vertex_field.hpp"
#include "io/atomic_file.hpp"
#include "io/file_format.hpp"
#include "io/mesh_io.hpp"
#include "io/mesh_writers.hpp"
#include "io/point_io.hpp"
#include "io/report_json.hpp"
#include "poreshell/io.hpp"

namespace poreshell {
namespace {

std::vector<Point> to_points(const std::vector<Vec3>& vertices) {
  std::vector<Point> points;
  points.reserve(vertices.size());
  for (const Vec3& v : vertices) points.push_back({v.x(), v.y(), v.z()});
  return points;
}

MeshInput to_mesh_input(const TriangleMesh& mesh, const MeshInputStats& stats, Unit unit, std::string name) {
  MeshInput input;
  input.dropped_degenerate = stats.dropped_degenerate;
  input.dropped_duplicate = stats.dropped_duplicate;
  input.mesh.vertices = to_points(mesh.vertices);
  input.mesh.triangles.assign(mesh.triangles.begin(), mesh.triangles.end());
  input.unit = unit;
  input.name = std::move(name);
  return input;
}

PointsInput to_points_input(const PointCloud& cloud, Unit unit, std::string name) {
  PointsInput input;
  input.points = to_points(cloud.points);
  input.patches.assign(cloud.triangles.begin(), cloud.triangles.end());
  input.unit = unit;
  input.name = std::move(name);
  return input;
}

}  // namespace

MeshInput load_mesh(const std::filesystem::path& path, Unit unit, const std::vector<std::string>& fields) {
  MeshInputStats stats;
  const TriangleMesh mesh = read_triangle_mesh(path, &stats);
  MeshInput input = to_mesh_input(mesh, stats, unit, path.string());
  // The file's vertices were welded and renumbered: each field's value is taken at the vertex's
  // position on the file's own faces, which is the value the file gives that vertex.
  for (const std::string& name : fields) {
    const VertexScalarField field = VertexScalarField::read_ply(path, name);
    std::vector<double>& values = input.vertex_fields[name];
    values.reserve(mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) values.push_back(field.at(v));
  }
  return input;
}

PointsInput load_points(const std::filesystem::path& path, Unit unit) {
  return to_points_input(read_point_cloud(path), unit, path.string());
}

MeshInput load_mesh_bytes(std::string_view bytes, const std::string& name, Unit unit) {
  MeshInputStats stats;
  const TriangleMesh mesh = read_triangle_mesh_bytes(bytes, lowercase_extension(name), name, &stats);
  return to_mesh_input(mesh, stats, unit, name);
}

PointsInput load_points_bytes(std::string_view bytes, const std::string& name, Unit unit) {
  return to_points_input(read_point_cloud_bytes(bytes, lowercase_extension(name), name), unit, name);
}

void save_mesh(const std::filesystem::path& path, const Mesh& mesh) {
  check_mesh_path(path);
  write_mesh(path, to_triangle_mesh(mesh));
}

void save_mesh(const std::filesystem::path& path, const Output& output) {
  check_mesh_path(path);
  if (output.pattern.empty() || lowercase_extension(path) != ".ply") {
    save_mesh(path, output.mesh);
    return;
  }
  TriangleMesh mesh;  // as it is: the pattern is per vertex
  for (const Point& p : output.mesh.vertices) mesh.vertices.emplace_back(p[0], p[1], p[2]);
  mesh.triangles.assign(output.mesh.triangles.begin(), output.mesh.triangles.end());
  write_ply(path, mesh, output.pattern, output.iso);
}

void check_output_path(const std::filesystem::path& path) {
  const std::filesystem::path dir =
      path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw Error(ErrorCode::io, "cannot write '" + path.string() + "': the directory '" + dir.string() +
                                   "' does not exist; create it or choose another path");
  if (std::filesystem::is_directory(path, ec))
    throw Error(ErrorCode::io, "cannot write '" + path.string() + "': it is a directory; give a file name");
  probe_output_folder(path);
}

void check_mesh_path(const std::filesystem::path& path) {
  check_output_path(path);
  check_output_extension(path);
}

std::filesystem::path output_path_for_level(const std::filesystem::path& output, double iso, bool several) {
  if (!several) return output;
  std::ostringstream name;
  name << output.stem().string() << "-iso" << iso << output.extension().string();
  return output.parent_path() / name.str();
}

std::string report_json(const Report& report, std::span<const Output> outputs) {
  return to_json(report, outputs).dump(2) + "\n";
}

void save_report(const std::filesystem::path& path, const Report& report, std::span<const Output> outputs) {
  check_output_path(path);
  const std::string text = report_json(report, outputs);
  write_atomically(
      path, [&](std::ostream& out) { out << text; }, false);
}

void save_holes_csv(const std::filesystem::path& path, std::span<const Hole> holes) {
  check_output_path(path);
  write_atomically(
      path,
      [&](std::ostream& out) {
        out << "x_mm,y_mm,z_mm,nx,ny,nz,diameter_mm,circularity,nearest_mm,axis_ratio,asked_mm\n"
            << std::setprecision(9);
        for (const Hole& h : holes)
          out << h.centre[0] << ',' << h.centre[1] << ',' << h.centre[2] << ',' << h.normal[0] << ','
              << h.normal[1] << ',' << h.normal[2] << ',' << h.diameter << ',' << h.circularity << ','
              << h.nearest << ',' << h.axis_ratio << ',' << h.asked_diameter << '\n';
      },
      false);
}

}  // namespace poreshell
