// libFuzzer harness: the --points reader on PLY bytes.

#include "harness.hpp"
#include "io/point_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return poreshell::fuzz::run(data, size, [](std::string_view bytes) {
    poreshell::read_point_cloud_bytes(bytes, ".ply", "fuzz.ply");
  });
}
