#pragma once
// Files: reading inputs, writing meshes, the JSON report and the hole table. Every writer writes a
// temporary file and renames it, so a failure leaves no partial file. Errors are poreshell::Error.

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "poreshell/export.hpp"
#include "poreshell/geometry.hpp"
#include "poreshell/options.hpp"
#include "poreshell/result.hpp"

namespace poreshell {

// Async-signal-safe: removes the temporary files of the writes in progress, for a SIGINT/SIGTERM handler
// that then calls _exit(); an interrupted write so leaves neither a partial file nor its temporary.
// (kill -9 leaves the temporary, named OUT.tmp-PID-N next to OUT, and never a file under OUT's name.)
PORESHELL_API void remove_partial_files() noexcept;

// A triangle mesh: STL, OBJ, PLY, OFF or 3MF by extension. `fields` names PLY vertex properties to
// read into MeshInput::vertex_fields (for keep_out_mask and grading by a field).
PORESHELL_API MeshInput load_mesh(const std::filesystem::path& path, Unit unit = Unit::mm,
                                  const std::vector<std::string>& fields = {});
// A point cloud: XYZ text (.xyz, .txt, .pts) or PLY vertices (faces, if any, become patches).
PORESHELL_API PointsInput load_points(const std::filesystem::path& path, Unit unit = Unit::mm);
// The same from a file's bytes in memory (an upload, a project's embedded model): `name`'s extension picks
// the format and names the input. No vertex fields.
PORESHELL_API MeshInput load_mesh_bytes(std::string_view bytes, const std::string& name,
                                        Unit unit = Unit::mm);
PORESHELL_API PointsInput load_points_bytes(std::string_view bytes, const std::string& name,
                                            Unit unit = Unit::mm);

// A mesh in mm: .stl (binary), .3mf, .obj or .ply (binary) by extension.
PORESHELL_API void save_mesh(const std::filesystem::path& path, const Mesh& mesh);
// An output: a preview's (one with `pattern`) as a .ply with vertex colours, dark where the holes are
// (other formats: its mesh alone); any other output as save_mesh(path, output.mesh).
PORESHELL_API void save_mesh(const std::filesystem::path& path, const Output& output);
// Checks before a long run that `path` can be written: its folder exists and it is not a folder.
PORESHELL_API void check_output_path(const std::filesystem::path& path);
// The same for a mesh, whose extension must also be one save_mesh writes.
PORESHELL_API void check_mesh_path(const std::filesystem::path& path);
// Where each level's mesh goes: OUT itself for one level, OUT-isoC.ext for several.
PORESHELL_API std::filesystem::path output_path_for_level(const std::filesystem::path& output, double iso,
                                                          bool several);

// The report as JSON text (the fields README.md lists), and written to a file.
PORESHELL_API std::string report_json(const Report& report, std::span<const Output> outputs = {});
PORESHELL_API void save_report(const std::filesystem::path& path, const Report& report,
                               std::span<const Output> outputs = {});

// The hole table as CSV: a header row, then one hole a line.
PORESHELL_API void save_holes_csv(const std::filesystem::path& path, std::span<const Hole> holes);

}  // namespace poreshell
