// libFuzzer harness: option combinations through the whole public pipeline at tiny sizes (issue 47:
// `--preview` of a mesh with the paper's parameters crashed, a combination of valid options, not a
// file). Each byte of the input chooses one thing, in the order of `decode` below (a missing byte is 0),
// so a seed can be written by hand: the input (a shape, a small open sleeve or cube mesh, a point
// cloud), holes in mm or the paper's parameters, preview, solver, layout, stop rule, mode, wall,
// offset, rim, keep-outs, grading, iso levels, the reduction and the model. Runs whose estimate exceeds
// a tiny band are skipped, so that each input takes milliseconds. A poreshell::Error is the normal
// answer to a combination that cannot be met; anything else (a crash, a sanitizer report, a leak, an
// exception of another type, a timeout) is a finding.
//
// Built with -DPORESHELL_FUZZ=ON (fuzz/CMakeLists.txt); without libFuzzer, -DPORESHELL_REPLAY_MAIN
// gives a main() that runs the files named on its command line once each.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "poreshell/poreshell.hpp"

namespace {

using namespace poreshell;

// The input's bytes, one a choice; 0 once they run out.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t next() { return at_ < size_ ? data_[at_++] : 0; }
  bool flag() { return (next() & 1) != 0; }
  int pick(int n) { return next() % n; }
  // lo .. hi, in 256 steps.
  double in(double lo, double hi) { return lo + (hi - lo) * next() / 255.0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

Mesh open_sleeve(double radius, double length, int segments, int rings) {
  Mesh m;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * std::numbers::pi * s / segments;
      m.vertices.push_back({radius * std::cos(a), radius * std::sin(a), length * r / rings});
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int i = r * segments + s, j = r * segments + (s + 1) % segments;
      m.triangles.push_back({i, j, j + segments});
      m.triangles.push_back({i, j + segments, i + segments});
    }
  return m;
}

Mesh cube(double size) {
  Mesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices.push_back({size * (k == 1 || k == 2 || k == 5 || k == 6),
                          size * (k == 2 || k == 3 || k == 6 || k == 7), size * (k >= 4)});
  m.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                 {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
  return m;
}

// Points on a sphere (a Fibonacci lattice), optionally with one stray point far out.
PointsInput sphere_points(double radius, int count, bool stray) {
  PointsInput p;
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1.0 - z * z);
    const double a = std::numbers::pi * (3.0 - std::sqrt(5.0)) * i;
    p.points.push_back({radius * r * std::cos(a), radius * r * std::sin(a), radius * z});
  }
  if (stray) p.points.push_back({10.0 * radius, 0.0, 0.0});
  return p;
}

Input decode_input(Bytes& b) {
  const double size = b.in(5.0, 60.0);  // mm
  switch (b.pick(6)) {
    case 0:
      return sphere();  // the paper's unit cube
    case 1:
      return sphere(size);
    case 2:
      return torus(size);
    case 3: {
      MeshInput in;
      in.mesh = open_sleeve(0.5 * size, size, 16, 3);
      return in;
    }
    case 4: {
      MeshInput in;
      in.mesh = cube(size);
      return in;
    }
    default:
      return sphere_points(0.5 * size, 400, b.flag());
  }
}

Options decode_options(Bytes& b) {
  Options o;
  o.threads = 1;
  o.max_memory_gb = 0.5;
  switch (b.pick(4)) {  // holes in mm, or the paper's parameters
    case 0:
      o.resolution = 9 + b.pick(16);  // 9 .. 24
      break;
    case 1:
      o.hole_diameter = b.in(0.5, 40.0);
      break;
    case 2:
      o.hole_diameter = b.in(0.5, 40.0);
      o.spacing = o.hole_diameter * b.in(1.0, 3.0);
      break;
    default:
      o.hole_diameter = b.in(0.5, 40.0);
      o.porosity = b.in(0.05, 0.6);
      break;
  }
  o.preview = b.flag();
  o.solver = b.flag() ? SolverKind::reference : SolverKind::fast;
  o.layout = static_cast<Layout>(b.pick(3));
  o.stop = static_cast<StopRule>(b.pick(3));
  o.mode = b.flag() ? Mode::narrow_volume : Mode::shell;
  if (o.mode == Mode::shell) {
    if (b.flag()) o.wall = b.in(0.1, 8.0);
    o.offset = static_cast<WallOffset>(b.pick(3));
  }
  if (b.flag()) o.rim = b.in(0.0, 10.0);
  if (b.flag()) o.keep_out.push_back({{b.in(-60, 60), b.in(-60, 60), b.in(-60, 60)}, b.in(0.5, 30.0)});
  if (b.flag()) {
    const double x = b.in(-60, 60), y = b.in(-60, 60), z = b.in(-60, 60);
    o.keep_out_boxes.push_back({{x, y, z}, {x + b.in(1, 40), y + b.in(1, 40), z + b.in(1, 40)}});
  }
  if (b.flag() && o.hole_diameter > 0.0) {
    Grade g;
    g.kind = Grade::Kind::axis;
    g.axis = b.pick(3);
    g.from_diameter = b.in(0.5, 20.0);
    g.to_diameter = b.in(0.5, 20.0);
    o.grade = g;
  }
  if (b.flag() && o.hole_diameter <= 0.0) o.iso = {b.in(-0.9, 0.9), b.in(-0.9, 0.9)};
  if (b.flag()) {
    o.max_triangles = 50 + 40 * b.next();
    o.max_deviation = b.in(0.01, 2.0);
  }
  if (o.hole_diameter <= 0.0) {
    o.alpha = b.in(0.0, 3000.0);
    o.phi_bar = b.in(-0.9, 0.9);
    o.epsilon_m = b.in(1.0, 8.0);
  }
  o.thin_feature_ratio = b.flag() ? 0.0 : b.in(0.5, 3.0);
  o.crease_angle = b.flag() ? 0.0 : b.in(10.0, 170.0);
  o.coarse_start = b.flag();
  o.inner = b.flag() ? InnerIteration::jacobi : InnerIteration::gauss_seidel;
  o.energy_every = b.pick(3);
  o.point_route = b.flag() ? PointRoute::paper : PointRoute::direct;
  o.keep_fragments = b.flag();
  o.max_steps = 1 + b.pick(6);
  o.seed = b.next();
  o.scale = b.flag() ? b.in(0.2, 3.0) : 1.0;
  return o;
}

// A tiny band: each input runs in milliseconds to a second.
constexpr double kMaxBandVoxels = 30000.0;

bool verbose = false;  // the replay says what each input did

void run_one(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  const Input input = decode_input(b);
  const Options options = decode_options(b);
  try {
    const Prepared prepared = prepare(input, options);
    const double band = estimate(prepared).band_voxels;
    if (!(band <= kMaxBandVoxels)) {
      if (verbose) std::printf("  skipped: about %.0f band voxels\n", band);
      return;
    }
    const Result r = perforate(prepared);
    for (const Output& out : r.outputs)
      if (options.preview && out.pattern.size() != out.mesh.vertices.size()) __builtin_trap();
    if (verbose)
      std::printf("  ran: %s%s, %s solver, %lld steps, %zu outputs, %zu triangles\n",
                  r.report.preview ? "preview of " : "", r.report.input.kind.c_str(),
                  r.report.solver.name.c_str(), static_cast<long long>(r.report.solver.steps),
                  r.outputs.size(),
                  r.outputs.empty() ? std::size_t{0} : r.outputs.front().mesh.triangles.size());
  } catch (const Error& e) {
    if (verbose) std::printf("  refused: %s\n", e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  run_one(data, size);
  return 0;
}

#ifdef PORESHELL_REPLAY_MAIN
// Runs each file named once (the seed corpus as a test, without libFuzzer).
int main(int argc, char** argv) {
  verbose = true;
  for (int i = 1; i < argc; ++i) {
    std::ifstream in(argv[i], std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "cannot read %s\n", argv[i]);
      return 1;
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::printf("%s\n", argv[i]);
    std::fflush(stdout);
    run_one(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  return 0;
}
#endif
