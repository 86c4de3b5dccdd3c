#pragma once
// Uploaded models: each file goes into the work folder under a name the studio chooses (never one a
// client gives), is read by the library's hardened readers, and is kept in memory for the runs.

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "poreshell/poreshell.hpp"

namespace studio {

struct Model {
  int id = 0;
  std::string name;  // the client's file name, for the report and the page only
  poreshell::Unit unit = poreshell::Unit::mm;
  std::filesystem::path path;     // in the work folder
  poreshell::Input input;         // a MeshInput or a PointsInput
  poreshell::Point min{}, max{};  // bounding box, mm (unit applied, before Options::scale)
  std::size_t vertices = 0, triangles = 0;
};

// The file extensions the studio takes, as the readers know them; empty when `name` has none of them.
std::string model_extension(std::string_view name);
// "m", "cm", "mm", "inch" -> the unit; throws std::invalid_argument naming the choices.
poreshell::Unit parse_unit(std::string_view text);

// Reads a model file (mesh, or points for .xyz/.txt/.pts and a face-less .ply). Throws poreshell::Error.
poreshell::Input read_model(const std::filesystem::path& path, poreshell::Unit unit, const std::string& name);
// The same from a file's bytes (a project's embedded model); `name`'s extension picks the format.
poreshell::Input read_model_bytes(std::string_view bytes, const std::string& name, poreshell::Unit unit);

class Models {
 public:
  explicit Models(std::filesystem::path folder) : folder_(std::move(folder)) {}
  // A new file name for an upload with this extension (".obj"); the caller writes it, then add()s it.
  std::filesystem::path new_path(const std::string& extension);
  // Reads the written file; on failure removes it and rethrows poreshell::Error.
  std::shared_ptr<const Model> add(const std::filesystem::path& path, const std::string& name,
                                   poreshell::Unit unit);
  // The model `id`, or the latest when id is 0; null when there is none.
  std::shared_ptr<const Model> get(int id) const;

 private:
  static constexpr std::size_t kKept = 3;  // older models are dropped (memory), their files removed
  std::filesystem::path folder_;
  mutable std::mutex mutex_;
  std::map<int, std::shared_ptr<const Model>> models_;
  int next_id_ = 1, next_file_ = 1;
};

}  // namespace studio
