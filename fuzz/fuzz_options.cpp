// libFuzzer harness: the command line as a whole. The input is one argument a line; the program's own
// parser reads them (flags, numbers, enums, lists, the grading and keep-out specs), the library
// validates the options, and the run's estimate is made for a shape (grid sizes from absurd values must
// be refused, not allocated). A usage error or a poreshell::Error is the normal answer.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "command_line.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> arguments{"poreshell"};
  for (std::size_t begin = 0; begin <= bytes.size() && arguments.size() < 64;) {
    const std::size_t end = std::min(bytes.find('\n', begin), bytes.size());
    arguments.emplace_back(bytes.substr(begin, end - begin));
    begin = end + 1;
  }
  // --help and --version answer on stdout and stop: nothing to check beyond not crashing.
  std::vector<const char*> argv;
  for (const std::string& a : arguments) argv.push_back(a.c_str());
  try {
    const std::optional<Command> command = parse_command_line(static_cast<int>(argv.size()), argv.data());
    if (!command) return 0;
    const poreshell::Input shape =
        poreshell::ShapeInput{poreshell::ShapeKind::sphere, command->radius, command->unit};
    const poreshell::Estimate estimate = poreshell::estimate(shape, command->options);
    if (!(estimate.band_voxels >= 0.0)) __builtin_trap();
  } catch (const UsageError&) {
  } catch (const poreshell::Error&) {
  }
  return 0;
}
