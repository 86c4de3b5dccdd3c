// libFuzzer harness: the --points reader on XYZ text bytes.

#include "harness.hpp"
#include "io/point_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return poreshell::fuzz::run(data, size, [](std::string_view bytes) {
    poreshell::read_point_cloud_bytes(bytes, ".xyz", "fuzz.xyz");
  });
}
