#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include "core/error.hpp"
#include "poreshell/io.hpp"

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

// The temporaries being written, for remove_partial_files() in a signal handler: fixed slots of plain
// characters (no allocation there), each published by its `live` flag after its name is complete.
struct LiveTemporary {
  std::atomic<bool> claimed{false};
  std::atomic<bool> live{false};
  std::array<char, 4096> name{};
};
std::array<LiveTemporary, 16> live_temporaries;
static_assert(std::atomic<bool>::is_always_lock_free, "used from a signal handler");

// Registers `tmp` before the file exists, so that no temporary is ever on disk unregistered. More
// concurrent writes than slots, or a longer name, go unregistered: a signal then leaves that
// temporary, which kill -9 leaves too and its name makes recognisable.
class LiveRegistration {
 public:
  explicit LiveRegistration(const fs::path& tmp) {
    const std::string& name = tmp.native();
    if (name.size() >= LiveTemporary{}.name.size()) return;
    for (LiveTemporary& slot : live_temporaries) {
      if (slot.claimed.exchange(true, std::memory_order_acquire)) continue;
      std::memcpy(slot.name.data(), name.c_str(), name.size() + 1);
      slot.live.store(true, std::memory_order_release);
      slot_ = &slot;
      return;
    }
  }
  ~LiveRegistration() {
    if (!slot_) return;
    slot_->live.store(false, std::memory_order_release);
    slot_->claimed.store(false, std::memory_order_release);
  }
  LiveRegistration(const LiveRegistration&) = delete;
  LiveRegistration& operator=(const LiveRegistration&) = delete;

 private:
  LiveTemporary* slot_ = nullptr;
};

// Why a file could not be created in `dir`, from open(2)'s errno, and what to do.
std::string creation_failure(const fs::path& path, const fs::path& dir, int error) {
  const std::string in = "cannot create a file in '" + dir.string() + "' to write '" + path.string() + "'";
  switch (error) {
    case ENAMETOOLONG:
      return "cannot write '" + path.string() + "': its file name is too long for the file system (" +
             std::to_string(path.filename().string().size()) +
             " bytes, and the temporary it is written to adds about 16); choose a shorter name";
    case EROFS:
      return in + ": the file system is read-only; choose another folder";
    case ENOSPC:
    case EDQUOT:
      return in + ": the disk is full (or the quota reached); free some space or choose another folder";
    default:
      return in + (error != 0 ? " (" + std::string(std::strerror(error)) + ")" : std::string()) +
             "; check that the directory is writable";
  }
}

}  // namespace

void probe_output_folder(const fs::path& path) {
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  // As long as the first temporary's name (".tmp-PID-0"), so that a name the write cannot use fails here;
  // not named like one, so that nothing watching for the write's temporary takes the probe for it.
  const fs::path probe(path.string() + ".chk-" + std::to_string(::getpid()) + "-0");
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    const int error = errno;
    if (error == EEXIST) return;  // a leftover of this process's name: the folder takes files
    throw InputError(creation_failure(path, dir, error));
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write, bool binary) {
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError("cannot write '" + path.string() + "': the directory '" + dir.string() +
                     "' does not exist; create it or choose another output path");
  if (fs::is_directory(path, ec))
    throw InputError("cannot write '" + path.string() + "': it is a directory; choose a file name");

  const fs::path tmp = temporary_name(path);
  const LiveRegistration registration(tmp);
  try {
    {
      std::ofstream out(
          tmp, binary ? std::ios::out | std::ios::trunc | std::ios::binary : std::ios::out | std::ios::trunc);
      if (!out) throw InputError(creation_failure(path, dir, errno));
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

void remove_partial_files() noexcept {
  for (LiveTemporary& slot : live_temporaries)
    if (slot.live.load(std::memory_order_acquire)) ::unlink(slot.name.data());
}

}  // namespace poreshell
