#pragma once
// Write-to-temporary-then-rename, so that readers never see a half-written output.

#include <filesystem>
#include <functional>
#include <ostream>

namespace poreshell {

// Calls `write` with a stream to a temporary file next to `path`, then renames it over `path`.
// On any failure the temporary file is removed and the error is rethrown.
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write,
                      bool binary = true);
// Creates and removes a file named as write_atomically's temporary for `path` would be, so that a folder
// that cannot be written, a read-only file system or a name too long is found before a long run, not
// after it. Throws InputError naming the cause (issue 47).
void probe_output_folder(const std::filesystem::path& path);
// remove_partial_files() (include/poreshell/io.hpp) is defined with it.

}  // namespace poreshell
