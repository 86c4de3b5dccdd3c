#pragma once
// Reading a whole input file into memory, so that every reader parses bytes (and can be fuzzed as such).

#include <filesystem>
#include <string>

namespace poreshell {

// The file's bytes. `kind` names the input in messages ("mesh", "point", "PLY"). Throws InputError for a
// missing path, a folder or other non-file, and a file that cannot be read.
std::string read_file_bytes(const std::filesystem::path& path, const std::string& kind);

}  // namespace poreshell
