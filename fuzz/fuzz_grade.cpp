// libFuzzer harness: the --grade parser, and the diameter function a parsed spec gives over a box.

#include <cmath>
#include <string>

#include "harness.hpp"
#include "pattern/grading.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return poreshell::fuzz::run(data, size, [](std::string_view bytes) {
    const poreshell::Grade grade = poreshell::parse_grade(std::string(bytes));
    if (grade.kind == poreshell::Grade::Kind::field) return;  // needs a PLY file: fuzz_vertex_field
    const poreshell::Box box{poreshell::Vec3::Zero(), poreshell::Vec3::Constant(10.0)};
    // An accepted spec must give a finite diameter everywhere; apply_grading would refuse the run.
    const auto diameter = poreshell::graded_diameter(grade, box, 5.0);
    for (const poreshell::Vec3& x : {box.min, box.max, poreshell::Vec3(1.0, 2.0, 3.0)})
      if (!std::isfinite(diameter(x))) __builtin_trap();
  });
}
