#pragma once
// Base64 for the page's binary arrays and a project's embedded model.

#include <optional>
#include <string>
#include <string_view>

namespace studio {

std::string base64_encode(std::string_view bytes);
// Null for text that is not base64 (whitespace is skipped).
std::optional<std::string> base64_decode(std::string_view text);

}  // namespace studio
