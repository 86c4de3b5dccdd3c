#include "process.hpp"

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>

namespace poreshell::test_support {

ProgramRun run_program(const std::string& program, const std::string& args, const std::filesystem::path& dir,
                       const std::filesystem::path& log_dir) {
  const std::filesystem::path out = log_dir / "stdout", err = log_dir / "stderr";
  const std::string command = "cd '" + dir.string() + "' && '" + program + "' " + args + " >'" +
                              out.string() + "' 2>'" + err.string() + "' </dev/null";
  ProgramRun run;
  run.status = std::system(command.c_str());
  run.exit_code = WIFEXITED(run.status) ? WEXITSTATUS(run.status) : -1;
  run.out = read_file(out);
  run.err = read_file(err);
  return run;
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) result.push_back(line);
  return result;
}

}  // namespace poreshell::test_support
