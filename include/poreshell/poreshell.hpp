#pragma once
// poreshell: uniform round pores on any surface, as one printable part.
//
//   #include <poreshell/poreshell.hpp>
//   poreshell::Options options;
//   options.hole_diameter = 8;  // mm
//   options.spacing = 14;
//   options.wall = 2;
//   poreshell::Result r = poreshell::perforate(poreshell::load_mesh("bunny.obj", poreshell::Unit::m),
//   options); poreshell::save_mesh("bunny.stl", r.outputs[0].mesh);
//
// The method is the nonlocal Cahn-Hilliard equation on a narrow band of voxels around the surface,
// with closest-point ghost values (docs/method.md).

#include "poreshell/error.hpp"
#include "poreshell/export.hpp"
#include "poreshell/geometry.hpp"
#include "poreshell/io.hpp"
#include "poreshell/options.hpp"
#include "poreshell/progress.hpp"
#include "poreshell/result.hpp"

namespace poreshell {

// Runs the whole job in memory: the pattern on the surface, the printable solid, its checks and its
// holes. Throws Error; writes nothing. Safe to call from several threads at once: each run has its own
// state, and the same input and options give the same bytes whatever else runs and whatever the
// thread count.
PORESHELL_API Result perforate(const Input& input, const Options& options, const RunControl& control = {});

PORESHELL_API const char* version();

}  // namespace poreshell
