// libFuzzer harness: the PLY vertex-field reader (--grade field:, --keep-out-mask), with the search it
// builds over the file's faces or points and one query, and the property listing its messages use.

#include "harness.hpp"
#include "input/vertex_field.hpp"
#include "io/ply_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return poreshell::fuzz::run(data, size, [](std::string_view bytes) {
    poreshell::ply::scalar_vertex_properties(bytes, "fuzz.ply");
    const auto field = poreshell::VertexScalarField::from_ply_bytes(bytes, "fuzz.ply", "quality");
    static_cast<void>(field.at(poreshell::Vec3(0.25, 0.5, 0.75)));
  });
}
