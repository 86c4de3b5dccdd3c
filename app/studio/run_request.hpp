#pragma once
// A preview's or a job's request: {"model": ID, "options": {...}, "keep_out_mask_values": [...]}, the
// options by the library's names (poreshell/option_table.hpp). A project file uses the same fields.

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "models.hpp"
#include "poreshell/poreshell.hpp"

namespace studio {

// The vertex field the painted mask becomes (Options::keep_out_mask names it).
inline constexpr const char* kMaskField = "studio_mask";

struct RunRequest {
  std::shared_ptr<const Model> model;
  poreshell::Options options;
  std::vector<double> mask;  // per vertex of the model's mesh, 0 or 1; empty: none painted
  std::string surface_id;    // a preview: the painted surface the page shows now ("surface_id"), if any
};

// Options and the painted mask from a request's "options" object (the mask may also be a sibling of
// "options" in `request`). Throws poreshell::Error (invalid_option) naming the option.
void read_options(const nlohmann::json& request, poreshell::Options& options, std::vector<double>& mask);

// Throws poreshell::Error (invalid_option or invalid_input) for a body that is no such request, an
// unknown model, a bad option or a mask that does not fit the model.
RunRequest parse_run_request(std::string_view body, const Models& models);

// The model's input with the mask as its vertex field, and `options` naming it when any vertex is painted.
// Throws poreshell::Error (invalid_option, keep_out_mask_values) for a mask of the wrong length or values.
poreshell::Input masked_input(const poreshell::Input& input, const std::vector<double>& mask,
                              poreshell::Options& options);

}  // namespace studio
