// libFuzzer harness: the --keep-out (X,Y,Z,R) and --keep-out-box (X0,Y0,Z0,X1,Y1,Z1) parsers, and the
// library's check of what they accept: a spec either is refused or gives finite numbers the options
// accept with a positive radius.

#include <cmath>
#include <cstdint>
#include <string>

#include "cli_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  poreshell::Options options;
  if (const auto v = numbers(text, 4)) options.keep_out.push_back({{(*v)[0], (*v)[1], (*v)[2]}, (*v)[3]});
  if (const auto v = numbers(text, 6))
    options.keep_out_boxes.push_back({{(*v)[0], (*v)[1], (*v)[2]}, {(*v)[3], (*v)[4], (*v)[5]}});
  try {
    poreshell::validate(options);
  } catch (const poreshell::Error&) {
    return 0;
  }
  for (const poreshell::KeepOutSphere& s : options.keep_out)
    if (!std::isfinite(s.centre[0] + s.centre[1] + s.centre[2]) || !(s.radius > 0.0)) __builtin_trap();
  for (const poreshell::KeepOutBox& b : options.keep_out_boxes)
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(b.min[i]) || !std::isfinite(b.max[i])) __builtin_trap();
  return 0;
}
