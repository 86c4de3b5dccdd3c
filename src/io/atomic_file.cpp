#include "io/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <string>
#include <system_error>

#include "core/error.hpp"

namespace poreshell {
namespace fs = std::filesystem;

namespace {

// Unique per process and per call, so concurrent writers to the same path never share a temp file.
fs::path temporary_name(const fs::path& path) {
  static std::atomic<unsigned long> counter{0};
  return fs::path(path.string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
}

void remove_quietly(const fs::path& p) {
  std::error_code ignored;
  fs::remove(p, ignored);
}

}  // namespace

void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write, bool binary) {
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError("cannot write '" + path.string() + "': the directory '" + dir.string() +
                     "' does not exist; create it or choose another output path");
  if (fs::is_directory(path, ec))
    throw InputError("cannot write '" + path.string() + "': it is a directory; choose a file name");

  const fs::path tmp = temporary_name(path);
  try {
    {
      std::ofstream out(
          tmp, binary ? std::ios::out | std::ios::trunc | std::ios::binary : std::ios::out | std::ios::trunc);
      if (!out)
        throw InputError("cannot create a file in '" + dir.string() + "' to write '" + path.string() +
                         "'; check that the directory is writable");
      write(out);
      out.flush();
      if (!out) throw InputError("writing '" + path.string() + "' failed (disk full?); nothing was written");
      out.close();
      if (!out) throw InputError("closing '" + path.string() + "' failed (disk full?); nothing was written");
    }
    fs::rename(tmp, path, ec);
    if (ec)
      throw InputError("cannot replace '" + path.string() + "': " + ec.message() +
                       "; check the permissions of the output path");
  } catch (...) {
    remove_quietly(tmp);
    throw;
  }
}

}  // namespace poreshell
