// libFuzzer harness: the mesh reader on PLY bytes, cleaning included (weld, degenerate triangles, topology).

#include "harness.hpp"
#include "io/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return poreshell::fuzz::run(data, size, [](std::string_view bytes) {
    poreshell::read_triangle_mesh_bytes(bytes, ".ply", "fuzz.ply");
  });
}
