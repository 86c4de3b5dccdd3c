// Faults while the program runs or writes (docs/reliability.md "Faults"): a full disk, kill -9 and
// SIGINT during the write, SIGTERM during the solve, the time budget and an address-space limit. Each leaves
// no file under the output's name and no partial file, and exits non-zero.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "process.hpp"

#ifndef PORESHELL_EXE
#error "PORESHELL_EXE must name the poreshell executable (see tests/CMakeLists.txt)"
#endif

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A unit sphere on a 160^3 grid: 0.2 s of solve and a 20 MB OBJ (the full isosurface, unreduced),
// whose writing lasts long enough for the test to act during it.
const std::vector<std::string> kBigWrite = {"--resolution", "160",     "--max-steps",     "1", "--tol",
                                            "1e-12",        "--quiet", "--max-deviation", "0"};

struct Folder {
  fs::path path;
  explicit Folder(const std::string& name)
      : path(fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Folder() { fs::remove_all(path); }
  std::vector<std::string> names() const {
    std::vector<std::string> result;
    for (const auto& entry : fs::directory_iterator(path)) result.push_back(entry.path().filename().string());
    return result;
  }
};

using poreshell::test_support::read_file;

// Starts the program with `args`, stdout to /dev/null and stderr to `err`.
pid_t start(const std::vector<std::string>& args, const fs::path& err) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen(err.c_str(), "w", stderr);
    std::vector<char*> argv{const_cast<char*>(PORESHELL_EXE)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(PORESHELL_EXE, argv.data());
    ::_exit(127);
  }
  return pid;
}

int wait_for(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

// Sends `signal_number` as soon as a file whose name contains ".tmp-" appears in `folder` (inotify,
// so within microseconds of its creation, long before a 20 MB write ends). Returns the wait status.
int signal_during_write(const Folder& folder, const std::vector<std::string>& args, int signal_number,
                        const fs::path& err) {
  const int watch = ::inotify_init1(IN_CLOEXEC);
  EXPECT_GE(watch, 0);
  EXPECT_GE(::inotify_add_watch(watch, folder.path.c_str(), IN_CREATE), 0);
  const pid_t pid = start(args, err);
  alignas(inotify_event) char buffer[4096];
  bool sent = false;
  while (!sent) {
    const ssize_t n = ::read(watch, buffer, sizeof buffer);
    if (n <= 0) break;
    for (ssize_t at = 0; at < n;) {
      const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
      if (event->len > 0 && std::string(event->name).find(".tmp-") != std::string::npos) {
        ::kill(pid, signal_number);
        sent = true;
        break;
      }
      at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
    }
  }
  ::close(watch);
  return wait_for(pid);
}

TEST(Faults, KillNineDuringTheWriteLeavesNoFileUnderTheFinalName) {
  const Folder out("poreshell-kill9");
  const int status = signal_during_write(out, with(kBigWrite, {"-o", (out.path / "big.obj").string()}),
                                         SIGKILL, out.path.string() + ".err");
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the write ended before the kill";
  for (const std::string& name : out.names()) {
    EXPECT_NE(name, "big.obj");
    EXPECT_EQ(name.rfind("big.obj.tmp-", 0), 0u) << "an unrecognisable leftover: " << name;
  }
}

TEST(Faults, SigintDuringTheWriteRemovesTheTemporary) {
  const Folder out("poreshell-sigint");
  const fs::path err = out.path.string() + ".err";
  const int status =
      signal_during_write(out, with(kBigWrite, {"-o", (out.path / "big.obj").string()}), SIGINT, err);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
  EXPECT_TRUE(out.names().empty()) << out.names().front();
  EXPECT_NE(read_file(err).find("poreshell: error: interrupted while writing"), std::string::npos)
      << read_file(err);
  fs::remove(err);
}

// SIGTERM while the solve runs (its progress line seen on stderr): the program is gone within a second
// (asserted with slack for a loaded machine; the figure is printed), nothing written.
TEST(Faults, SigtermDuringTheSolveStopsAtOnce) {
  const Folder out("poreshell-sigterm");
  const fs::path err = out.path.string() + ".err";
  const pid_t pid = start({"--resolution", "160", "--alpha", "400", "--max-steps", "100000", "--tol", "1e-12",
                           "--progress", "json", "-o", (out.path / "s.stl").string()},
                          err);
  const auto give_up = Clock::now() + std::chrono::seconds(120);
  while (read_file(err).find("\"stage\": \"solve\"") == std::string::npos && Clock::now() < give_up)
    ::usleep(20000);
  const auto sent = Clock::now();
  ::kill(pid, SIGTERM);
  const int status = wait_for(pid);
  const double seconds = std::chrono::duration<double>(Clock::now() - sent).count();
  std::printf("stopped %.3f s after SIGTERM\n", seconds);
  EXPECT_LT(seconds, 5.0);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  EXPECT_TRUE(out.names().empty());
  EXPECT_NE(read_file(err).find("poreshell: error: interrupted; nothing was written"), std::string::npos);
  fs::remove(err);
}

TEST(Faults, TimeBudgetStopsTheRunWithItsMessage) {
  const Folder out("poreshell-budget");
  const fs::path err = out.path.string() + ".err";
  const auto begun = Clock::now();
  const int status =
      wait_for(start({"--resolution", "160", "--alpha", "400", "--max-steps", "100000", "--tol", "1e-12",
                      "--quiet", "--max-seconds", "1", "-o", (out.path / "s.stl").string()},
                     err));
  std::printf("ended %.2f s after the start with --max-seconds 1\n",
              std::chrono::duration<double>(Clock::now() - begun).count());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_TRUE(out.names().empty());
  const std::string message = read_file(err);
  EXPECT_NE(message.find("poreshell: error: the run passed its time budget of 1 s (--max-seconds)"),
            std::string::npos)
      << message;
  fs::remove(err);
}

// Under `ulimit -v` (RLIMIT_AS) a run estimated above what is left of the address space is refused
// before it starts, naming the limit (issue 47: a run estimated at 3.4 GB started under 2.9 GB and
// failed after 74 s). The unit sphere at 450 points is estimated at 1.1 GB.
TEST(Faults, AnAddressSpaceLimitIsRespectedBeforeTheRun) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: no ulimit -v fits it";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: no ulimit -v fits it";
#endif
#endif
  const Folder out("poreshell-ulimit");
  const fs::path err = out.path.string() + ".err";
  const std::string command = "ulimit -v 700000 && '" + std::string(PORESHELL_EXE) +
                              "' --resolution 450 --quiet -o '" + (out.path / "s.stl").string() +
                              "' >/dev/null 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_TRUE(out.names().empty());
  const std::string message = read_file(err);
  EXPECT_NE(message.find("left under the address-space limit (ulimit -v)"), std::string::npos) << message;
  EXPECT_NE(message.find("use --resolution"), std::string::npos) << message;
  fs::remove(err);
}

// A 64 kB tmpfs as the output folder, mounted in a private mount namespace (unshare -rm: no root
// needed, nothing left mounted); skipped where user namespaces are not allowed.
TEST(Faults, FullDiskFailsCleanly) {
  const Folder out("poreshell-full");
  const fs::path log = out.path.string() + ".log";
  const fs::path script = out.path.string() + ".sh";
  std::ofstream(script) << "mount -t tmpfs -o size=64k tmpfs '" << out.path.string() << "' || exit 77\n'"
                        << PORESHELL_EXE << "' --resolution 60 --max-steps 1 --quiet -o '"
                        << (out.path / "s.stl").string() << "' 2>&1 >/dev/null\necho \"exit $?\"\nls -A '"
                        << out.path.string() << "'\n";
  const std::string command = "unshare -rm sh '" + script.string() + "' >'" + log.string() + "' 2>/dev/null";
  const int status = std::system(command.c_str());
  const std::string text = read_file(log);
  fs::remove(log);
  fs::remove(script);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 77) GTEST_SKIP() << "cannot mount a tmpfs here";
  ASSERT_NE(text.find("exit 1\n"), std::string::npos) << text;
  // The error line, the exit line and no listing: nothing in the folder.
  EXPECT_NE(text.find("poreshell: error: writing '"), std::string::npos) << text;
  EXPECT_NE(text.find("(disk full?); nothing was written"), std::string::npos) << text;
  EXPECT_EQ(text.substr(text.find("exit 1\n") + 7), "") << "left in the full folder: " << text;
}

}  // namespace
