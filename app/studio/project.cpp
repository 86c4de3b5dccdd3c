#include "project.hpp"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "models.hpp"
#include "poreshell/base64.hpp"
#include "run_request.hpp"

namespace studio {

namespace fs = std::filesystem;
using poreshell::Error;
using poreshell::ErrorCode;

Project load_project(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(ErrorCode::io, "cannot read the project " + file.string());
  std::ostringstream text;
  text << in.rdbuf();
  const nlohmann::json project = nlohmann::json::parse(text.str(), nullptr, false);
  if (project.is_discarded() || !project.is_object() || !project.contains("model") ||
      !project["model"].is_object())
    throw Error(ErrorCode::invalid_input, file.string() + " is not a studio project (no \"model\" object)");
  const nlohmann::json& model = project["model"];
  const std::string name = model.value("name", std::string{});
  if (model_extension(name).empty())
    throw Error(ErrorCode::invalid_input, "the project's model has no name with a model extension");
  poreshell::Unit unit{};
  try {
    unit = parse_unit(model.value("units", std::string("mm")));
  } catch (const std::invalid_argument& e) {
    throw Error(ErrorCode::invalid_input, std::string("the project's model: ") + e.what());
  }
  Project out;
  if (model.contains("data") && model["data"].is_string()) {
    const auto bytes = poreshell::base64_decode(model["data"].get<std::string>());
    if (!bytes) throw Error(ErrorCode::invalid_input, "the project's embedded model is not base64");
    out.input = read_model_bytes(*bytes, name, unit);
  } else if (model.contains("path") && model["path"].is_string()) {
    fs::path path = model["path"].get<std::string>();
    if (path.is_relative()) path = file.parent_path() / path;
    out.input = read_model(path, unit, name);
  } else {
    throw Error(ErrorCode::invalid_input, "the project's model has neither \"data\" nor \"path\"");
  }
  std::vector<double> mask;
  read_options(project, out.options, mask);
  out.input = masked_input(out.input, mask, out.options);
  return out;
}

}  // namespace studio
