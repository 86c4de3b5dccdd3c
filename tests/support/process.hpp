#pragma once
// Running a program the way a script does: a shell command line in a folder, stdin from /dev/null,
// its exit code and what it printed. The end-to-end tests of app/ share it.

#include <filesystem>
#include <string>
#include <vector>

namespace poreshell::test_support {

struct ProgramRun {
  int status = -1;     // as std::system gives it (WIFEXITED, WEXITSTATUS)
  int exit_code = -1;  // -1 where a signal ended the program
  std::string out, err;
};

// Runs `program` with `args` (shell syntax) in `dir`. Its stdout and stderr go to the files "stdout" and
// "stderr" in `log_dir` (kept outside `dir` by callers that check what a run left in it) and come back
// in the result.
ProgramRun run_program(const std::string& program, const std::string& args, const std::filesystem::path& dir,
                       const std::filesystem::path& log_dir);

// A file's bytes ("" where it cannot be read).
std::string read_file(const std::filesystem::path& path);

// The non-empty lines of `text`.
std::vector<std::string> lines(const std::string& text);

}  // namespace poreshell::test_support
