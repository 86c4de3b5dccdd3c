#pragma once
// Small helpers shared by the file readers and writers.

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace poreshell {

// The file's extension in lower case, with its dot (".stl"): formats are chosen by extension.
inline std::string lowercase_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
  return ext;
}

}  // namespace poreshell
