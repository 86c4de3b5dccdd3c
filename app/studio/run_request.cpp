#include "run_request.hpp"

#include <algorithm>

#include "poreshell/option_table.hpp"

namespace studio {

using poreshell::Error;
using poreshell::ErrorCode;

namespace {
constexpr const char* kMaskName = "keep_out_mask_values";

std::vector<double> read_mask(const nlohmann::json& values) {
  if (!values.is_array())
    throw Error(ErrorCode::invalid_option, "`keep_out_mask_values` must be a list of 0 and 1, one per vertex",
                kMaskName);
  std::vector<double> mask;
  mask.reserve(values.size());
  for (const nlohmann::json& v : values) {
    if (!v.is_number() || (v.get<double>() != 0.0 && v.get<double>() != 1.0))
      throw Error(ErrorCode::invalid_option, "`keep_out_mask_values` holds a value other than 0 and 1",
                  kMaskName);
    mask.push_back(v.get<double>());
  }
  return mask;
}
}  // namespace

void read_options(const nlohmann::json& request, poreshell::Options& options, std::vector<double>& mask) {
  nlohmann::json given = request.contains("options") ? request["options"] : nlohmann::json::object();
  if (!given.is_object())
    throw Error(ErrorCode::invalid_option, "\"options\" must be a JSON object", "options");
  mask.clear();
  if (given.contains(kMaskName)) {
    mask = read_mask(given[kMaskName]);
    given.erase(kMaskName);
  } else if (request.contains(kMaskName)) {
    mask = read_mask(request[kMaskName]);
  }
  options = poreshell::options_from_json(given.dump());
}

RunRequest parse_run_request(std::string_view body, const Models& models) {
  const nlohmann::json request = nlohmann::json::parse(body, nullptr, false);
  if (request.is_discarded() || !request.is_object())
    throw Error(ErrorCode::invalid_input, "the request's body is not a JSON object");
  RunRequest run;
  int id = 0;
  if (request.contains("model")) {
    if (!request["model"].is_number_integer())
      throw Error(ErrorCode::invalid_input, "\"model\" must be the id /api/model gave");
    id = request["model"].get<int>();
  }
  run.model = models.get(id);
  if (!run.model) throw Error(ErrorCode::invalid_input, "no model: upload one first (POST /api/model)");
  read_options(request, run.options, run.mask);
  if (request.contains("surface_id") && request["surface_id"].is_string())
    run.surface_id = request["surface_id"].get<std::string>();
  return run;
}

poreshell::Input masked_input(const poreshell::Input& input, const std::vector<double>& mask,
                              poreshell::Options& options) {
  poreshell::Input out = input;
  if (mask.empty() || std::none_of(mask.begin(), mask.end(), [](double v) { return v != 0.0; })) return out;
  auto* mesh = std::get_if<poreshell::MeshInput>(&out);
  if (!mesh)
    throw Error(ErrorCode::invalid_option, "`keep_out_mask_values` needs a mesh model, not a point cloud",
                kMaskName);
  if (mask.size() != mesh->mesh.vertices.size())
    throw Error(ErrorCode::invalid_option,
                "`keep_out_mask_values` has " + std::to_string(mask.size()) + " values for a model of " +
                    std::to_string(mesh->mesh.vertices.size()) + " vertices",
                kMaskName);
  mesh->vertex_fields[kMaskField] = mask;
  options.keep_out_mask = kMaskField;
  return out;
}

}  // namespace studio
