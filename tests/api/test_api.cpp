// The public API (include/poreshell/): meshes in memory give the bytes a file gives, runs cancel at every
// stage, concurrent runs equal sequential ones, and every option's error names the option.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace poreshell;

namespace {

using test_support::uv_sphere;

// A small, quick request: 12 mm holes on a 40 mm sphere. The 4 mm wall meshes the shell at 1.33 mm, a
// quarter of the triangles of a 2 mm wall: these runs are among the sanitizer suite's longest.
Options quick_options() {
  Options o;
  o.hole_diameter = 12.0;
  o.spacing = 20.0;
  o.wall = 4.0;
  return o;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Api, MeshInMemoryGivesTheBytesOfTheSameMeshReadFromAFile) {
  const TempDir dir;
  MeshInput in;
  in.mesh = uv_sphere(40.0, 24, 48);
  // OBJ keeps the vertex order and the shared vertices, so the file holds exactly this mesh.
  {
    std::ofstream obj(dir / "sphere.obj");
    obj.precision(17);
    for (const Point& v : in.mesh.vertices) obj << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    for (const Triangle& t : in.mesh.triangles)
      obj << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  }
  Options o = quick_options();
  o.max_deviation = 0.0;  // the reduction's bytes follow its input's; the input is what this test is about
  const Result memory = perforate(in, o);
  const Result file = perforate(load_mesh(dir / "sphere.obj"), o);
  save_mesh(dir / "memory.stl", memory.outputs.at(0).mesh);
  save_mesh(dir / "file.stl", file.outputs.at(0).mesh);
  EXPECT_EQ(bytes_of(dir / "memory.stl"), bytes_of(dir / "file.stl"));
  EXPECT_GT(memory.report.outputs.at(0).pores_from_euler, 10);
}

// A file's bytes in memory read as the file does (an upload, a project's embedded model), its format by
// the name's extension, and refused alike when malformed.
TEST(Api, MeshFromBytesIsTheMeshFromTheFile) {
  const TempDir dir;
  {
    std::ofstream obj(dir / "sphere.obj");
    obj.precision(17);
    const Mesh m = uv_sphere(40.0, 12, 24);
    for (const Point& v : m.vertices) obj << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    for (const Triangle& t : m.triangles)
      obj << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  }
  const MeshInput file = load_mesh(dir / "sphere.obj", Unit::cm);
  const MeshInput bytes = load_mesh_bytes(bytes_of(dir / "sphere.obj"), "Sphere.OBJ", Unit::cm);
  EXPECT_EQ(bytes.mesh.vertices, file.mesh.vertices);
  EXPECT_EQ(bytes.mesh.triangles, file.mesh.triangles);
  EXPECT_EQ(bytes.unit, Unit::cm);
  EXPECT_EQ(bytes.name, "Sphere.OBJ");
  EXPECT_EQ(load_points_bytes("0 0 0\n1 0 0\n0 1 0\n", "p.xyz").points.size(), 3u);
  EXPECT_THROW(load_mesh_bytes("v 0 0 0\nf 1 2\n", "bad.obj"), Error);
}

// Cancelling from the progress callback stops the run at that stage: the exception reaches the caller
// and no later stage starts. With the flag, the run ends with Error(cancelled).
TEST(Api, CancelsAtEveryStage) {
  const Input input = sphere(40.0);
  std::vector<std::string> stages;
  perforate(input, quick_options(), {[&](const Progress& p) {
              if (stages.empty() || stages.back() != p.stage) stages.emplace_back(p.stage);
            }});
  const std::vector<std::string> expected{"input", "band", "solve", "shell", "mesh", "holes"};
  ASSERT_EQ(stages, expected);
  struct Stop {};
  for (const std::string& stage : stages) {
    std::vector<std::string> seen;
    EXPECT_THROW(perforate(input, quick_options(), {[&](const Progress& p) {
                             seen.emplace_back(p.stage);
                             if (p.stage == stage) throw Stop{};
                           }}),
                 Stop)
        << stage;
    EXPECT_EQ(seen.back(), stage);
    std::atomic<bool> cancel{false};
    std::string last;
    try {
      perforate(input, quick_options(),
                {[&](const Progress& p) {
                   last = p.stage;
                   if (p.stage == stage) cancel = true;
                 },
                 &cancel});
      ADD_FAILURE() << "not cancelled at " << stage;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::cancelled) << e.what();
      EXPECT_EQ(last, stage) << "a later stage started";
    }
  }
}

TEST(Api, ConcurrentRunsGiveTheBytesOfSequentialRuns) {
  Options a = quick_options(), b = quick_options();
  b.seed = 7;
  b.threads = 1;
  const Result first = perforate(sphere(40.0), a), second = perforate(torus(30.0), b);
  Result first_again, second_again;
  std::thread t1([&] { first_again = perforate(sphere(40.0), a); });
  std::thread t2([&] { second_again = perforate(torus(30.0), b); });
  t1.join();
  t2.join();
  EXPECT_EQ(first.outputs.at(0).mesh.vertices, first_again.outputs.at(0).mesh.vertices);
  EXPECT_EQ(first.outputs.at(0).mesh.triangles, first_again.outputs.at(0).mesh.triangles);
  EXPECT_EQ(second.outputs.at(0).mesh.vertices, second_again.outputs.at(0).mesh.vertices);
  EXPECT_EQ(second.outputs.at(0).mesh.triangles, second_again.outputs.at(0).mesh.triangles);
  EXPECT_EQ(second.report.threads, 1);
}

// Every option out of range gets Error(invalid_option) naming it, in option() and in the message.
TEST(Api, EveryOptionsErrorNamesTheOption) {
  const std::vector<std::pair<std::string, std::function<void(Options&)>>> cases{
      {"resolution", [](Options& o) { o.resolution = 3; }},
      {"resolution", [](Options& o) { o.resolution = 100000; }},
      {"voxel_size", [](Options& o) { o.voxel_size = -1; }},
      {"voxel_size", [](Options& o) { o.voxel_size = NAN; }},
      {"wall", [](Options& o) { o.wall = -2; }},
      {"wall",
       [](Options& o) {
         o.mode = Mode::narrow_volume;
         o.wall = 2;
       }},
      {"max_memory_gb", [](Options& o) { o.max_memory_gb = -1; }},
      {"rim", [](Options& o) { o.rim = -1; }},
      {"keep_out",
       [](Options& o) {
         o.keep_out.push_back({{0, 0, 0}, 0.0});
       }},
      {"keep_out",
       [](Options& o) {
         o.keep_out.push_back({{NAN, 0, 0}, 1.0});
       }},
      {"keep_out_boxes",
       [](Options& o) {
         o.keep_out_boxes.push_back({{1, 0, 0}, {0, 1, 1}});
       }},
      {"solver",
       [](Options& o) {
         o.rim = 2;
         o.solver = SolverKind::reference;
       }},
      {"epsilon_m", [](Options& o) { o.epsilon_m = 0; }},
      {"tolerance", [](Options& o) { o.tolerance = 0; }},
      {"fast_tolerance", [](Options& o) { o.fast_tolerance = -1; }},
      {"inner_tolerance", [](Options& o) { o.inner_tolerance = 0; }},
      {"min_stabilisation", [](Options& o) { o.min_stabilisation = -1; }},
      {"max_steps", [](Options& o) { o.max_steps = 0; }},
      {"energy_every", [](Options& o) { o.energy_every = -1; }},
      {"initial_amplitude", [](Options& o) { o.initial_amplitude = -1; }},
      {"threads", [](Options& o) { o.threads = -1; }},
      // One way of asking (issue 48): a paper's parameter given with holes in mm, even at its default.
      {"alpha",
       [](Options& o) {
         o.hole_diameter = 6;
         o.alpha = PaperModel::alpha;
       }},
      {"iso",
       [](Options& o) {
         o.porosity = 0.3;
         o.iso = {PaperModel::iso};
       }},
      {"iso", [](Options& o) { o.iso = {1.5}; }},
      {"iso",
       [](Options& o) {
         o.iso = {0.1, 0.1};
       }},
      {"alpha", [](Options& o) { o.alpha = -1; }},
      {"dt_h", [](Options& o) { o.dt_h = 0; }},
      {"phi_bar", [](Options& o) { o.phi_bar = 2; }},
      {"hole_diameter", [](Options& o) { o.hole_diameter = -6; }},
      {"grade", [](Options& o) { o.grade = Grade{}; }},
      {"max_triangles", [](Options& o) { o.max_triangles = 2; }},
      {"max_deviation", [](Options& o) { o.max_deviation = -1; }},
      {"lean",
       [](Options& o) {
         o.lean = true;
         o.max_deviation = 0;
       }},
  };
  std::set<std::string> named;
  for (const auto& [option, spoil] : cases) {
    Options o;
    spoil(o);
    try {
      validate(o);
      ADD_FAILURE() << option << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_option) << option;
      EXPECT_EQ(e.option(), option) << e.what();
      EXPECT_NE(std::string(e.what()).find("`" + option + "`"), std::string::npos) << e.what();
      named.insert(e.option());
    }
  }
  // perforate() checks the same before it starts.
  Options o;
  o.max_steps = 0;
  EXPECT_THROW(perforate(sphere(), o), Error);
  EXPECT_GE(named.size(), 25u);
}

TEST(Api, BadMeshesAreInvalidInputNotCrashes) {
  MeshInput in;
  in.mesh = uv_sphere(10.0, 8, 16);
  in.mesh.vertices[3][1] = NAN;
  try {
    perforate(in, quick_options());
    ADD_FAILURE() << "a NaN vertex was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input) << e.what();
  }
  in.mesh = uv_sphere(10.0, 8, 16);
  in.mesh.triangles[0][1] = 100000;
  EXPECT_THROW(perforate(in, quick_options()), Error);
  EXPECT_THROW(perforate(MeshInput{}, quick_options()), Error);
  EXPECT_THROW(perforate(PointsInput{}, quick_options()), Error);
}

}  // namespace
