#include "io/file_bytes.hpp"

#include <fmt/format.h>

#include <fstream>
#include <system_error>

#include "core/error.hpp"

namespace poreshell {

std::string read_file_bytes(const std::filesystem::path& path, const std::string& kind) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status))
    throw InputError(fmt::format("{} file '{}' does not exist: check the path", kind, path.string()));
  if (std::filesystem::is_directory(status))
    throw InputError(fmt::format("{} file '{}' is a folder, not a file: give the path of a file in it", kind,
                                 path.string()));
  if (!std::filesystem::is_regular_file(status))
    throw InputError(fmt::format("{} file '{}' is not a regular file: give the path of a file on disk", kind,
                                 path.string()));
  std::ifstream in(path, std::ios::binary);
  const auto size = std::filesystem::file_size(path, ec);
  if (!in || ec)
    throw InputError(fmt::format("cannot read {} file '{}': check its permissions", kind, path.string()));
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<std::size_t>(in.gcount()));  // a file that shrank while being read
  return bytes;
}

}  // namespace poreshell
