#pragma once
// Base64 (RFC 4648, with padding): the viewer page's binary arrays, and the studio's meshes and
// project files, which carry a model's bytes in JSON.

#include <optional>
#include <string>
#include <string_view>

#include "poreshell/export.hpp"

namespace poreshell {

PORESHELL_API std::string base64_encode(std::string_view bytes);
// Null for text that is not base64 (whitespace is skipped).
PORESHELL_API std::optional<std::string> base64_decode(std::string_view text);

}  // namespace poreshell
