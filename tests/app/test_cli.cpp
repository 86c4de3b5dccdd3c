// The poreshell program end to end: the contract scripts rely on (exit codes, one-line errors, no
// partial output, file names, report keys, thread-count independence).

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "process.hpp"

#ifndef PORESHELL_EXE
#error "PORESHELL_EXE must name the poreshell executable (see tests/CMakeLists.txt)"
#endif

namespace {

namespace fs = std::filesystem;

// A small run that finishes in well under a second in Release: alpha * eps^2 < 1/4 keeps the
// pattern-forming regime well posed on the coarse grid.
const std::string kSmallRun = "--shape sphere --resolution 33 --alpha 84 --max-steps 5 --tol 1e-12 --quiet";

using Outcome = poreshell::test_support::ProgramRun;
using poreshell::test_support::lines;
using poreshell::test_support::read_file;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("poreshell_test_cli_" + std::to_string(::getpid()) + "_" + std::string(info->name()));
    fs::remove_all(root_);
    fs::create_directories(work());
    fs::create_directories(root_ / "log");  // captured streams live outside work() so it holds only outputs
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }

  fs::path work() const { return root_ / "work"; }

  // Runs poreshell with `args` (shell syntax) in work().
  Outcome run(const std::string& args) const {
    return poreshell::test_support::run_program(PORESHELL_EXE, args, work(), root_ / "log");
  }

  std::vector<std::string> files_in_work() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(work()))
      names.push_back(entry.path().filename().string());
    return names;
  }

  // One line on stderr, in the documented form.
  static void expect_one_error_line(const Outcome& o) {
    const auto l = lines(o.err);
    ASSERT_EQ(l.size(), 1u) << o.err;
    EXPECT_EQ(l[0].rfind("poreshell: error: ", 0), 0u) << l[0];
    EXPECT_GT(l[0].size(), std::string("poreshell: error: ").size() + 10)
        << "the message should say what to fix";
  }

  fs::path root_;
};

std::uint32_t stl_triangle_count(const std::string& bytes) {
  std::uint32_t n = 0;
  for (int b = 3; b >= 0; --b)
    n = (n << 8) | static_cast<unsigned char>(bytes.at(80 + static_cast<std::size_t>(b)));
  return n;
}

TEST_F(Cli, HelpExitsZeroAndMentionsEveryOption) {
  const Outcome o = run("--help");
  EXPECT_EQ(o.exit_code, 0) << o.err;
  for (const char* option : {"--shape",      "--resolution",    "--alpha",
                             "--epsilon-m",  "--dt-h",          "--tol",
                             "--max-steps",  "--seed",          "--iso",
                             "--threads",    "--phi-bar",       "--inner",
                             "--inner-tol",  "--mesh",          "-o",
                             "--report",     "--quiet",         "--version",
                             "--units",      "--mode",          "--wall",
                             "--offset",     "--points",        "--point-route",
                             "--solver",     "--fast-tol",      "--min-stabilisation",
                             "--max-memory", "--hole-diameter", "--spacing",
                             "--porosity",   "--grade",         "--radius"})
    EXPECT_NE(o.out.find(option), std::string::npos) << option << " missing from --help:\n" << o.out;
  EXPECT_TRUE(files_in_work().empty());
}

TEST_F(Cli, VersionExitsZero) {
  const Outcome o = run("--version");
  EXPECT_EQ(o.exit_code, 0) << o.err;
  EXPECT_EQ(o.out.rfind("poreshell ", 0), 0u) << o.out;
}

TEST_F(Cli, UnknownFlagIsAUsageError) {
  const Outcome o = run("--no-such-flag -o X.stl");
  EXPECT_EQ(o.exit_code, 2);
  expect_one_error_line(o);
  EXPECT_NE(o.err.find("--no-such-flag"), std::string::npos) << o.err;
  EXPECT_TRUE(files_in_work().empty());
}

TEST_F(Cli, MissingOutputIsAUsageError) {
  const Outcome o = run("--resolution 33");
  EXPECT_EQ(o.exit_code, 2);
  expect_one_error_line(o);
  EXPECT_TRUE(files_in_work().empty());
}

TEST_F(Cli, AViewAloneNeedsNoMeshFile) {
  // A designer's first look: the preview's page, no mesh file. The summary says none was written.
  const Outcome o = run("--shape sphere --radius 20 --hole-diameter 6 --spacing 10 --preview --html v.html");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  EXPECT_EQ(files_in_work(), std::vector<std::string>{"v.html"});
  EXPECT_NE(o.out.find("no file (no -o)"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("also     v.html (viewer)"), std::string::npos) << "the summary names the page:\n"
                                                                       << o.out;
  const Outcome table =
      run("--shape sphere --radius 20 --hole-diameter 6 --spacing 10 --preview --holes h.csv -q");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_TRUE(fs::exists(work() / "h.csv"));
}

TEST_F(Cli, ViewerStandsObjAndPlyScansOnYAndTheRestOnZ) {
  // A 40 mm cube, as OBJ (scans' y up) and as STL (printing's z up).
  const std::string corners[8] = {"0 0 0",  "40 0 0",  "40 40 0",  "0 40 0",
                                  "0 0 40", "40 0 40", "40 40 40", "0 40 40"};
  const int faces[12][3] = {{1, 3, 2}, {1, 4, 3}, {5, 6, 7}, {5, 7, 8}, {1, 2, 6}, {1, 6, 5},
                            {2, 3, 7}, {2, 7, 6}, {3, 4, 8}, {3, 8, 7}, {4, 1, 5}, {4, 5, 8}};
  std::ofstream obj(work() / "cube.obj"), stl(work() / "cube.stl");
  for (const std::string& c : corners) obj << "v " << c << "\n";
  stl << "solid cube\n";
  for (const auto& f : faces) {
    obj << "f " << f[0] << " " << f[1] << " " << f[2] << "\n";
    stl << "facet normal 0 0 0\nouter loop\n";
    for (const int v : f) stl << "vertex " << corners[v - 1] << "\n";
    stl << "endloop\nendfacet\n";
  }
  stl << "endsolid cube\n";
  obj.close();
  stl.close();
  for (const auto& [file, up] : {std::pair{"cube.obj", "y"}, std::pair{"cube.stl", "z"}}) {
    const Outcome o =
        // --thin-features 0: each of a low-poly cube's 8 vertices is a corner, which the thickness test
        // takes for a thin part, so no hole would fit (refused since issue 47).
        run(std::string("--mesh ") + file +
            " --hole-diameter 6 --spacing 10 --thin-features 0 --preview -q --html v.html");
    ASSERT_EQ(o.exit_code, 0) << o.err;
    EXPECT_NE(read_file(work() / "v.html").find(std::string("\"up_axis\":\"") + up + "\""), std::string::npos)
        << file;
  }
}

TEST_F(Cli, InvalidValuesFailWithAMessageAndNoOutput) {
  for (const char* args : {"--resolution 2 -o X.stl --report X.json", "--alpha -1 -o X.stl --report X.json",
                           "--phi-bar 2 -o X.stl --report X.json --quiet"}) {
    const Outcome o = run(args);
    EXPECT_TRUE(o.exit_code == 1 || o.exit_code == 2) << args << ": exit " << o.exit_code;
    expect_one_error_line(o);
    EXPECT_TRUE(files_in_work().empty()) << args;
  }
}

TEST_F(Cli, ShapeAndMeshAreExclusive) {
  const Outcome o = run("--shape torus --mesh bunny.obj -o X.stl");
  EXPECT_EQ(o.exit_code, 2);
  expect_one_error_line(o);
  EXPECT_TRUE(files_in_work().empty());
}

TEST_F(Cli, MissingOrBadMeshFailsWithItsNameAndNoOutput) {
  {
    std::ofstream bad(work() / "bad.obj");
    bad << "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n";
  }
  for (const char* mesh : {"missing.stl", "bad.obj"}) {
    const Outcome o =
        run(std::string("--mesh ") + mesh + " --resolution 33 -o X.stl --report X.json --quiet");
    EXPECT_EQ(o.exit_code, 1) << mesh;
    expect_one_error_line(o);
    EXPECT_NE(o.err.find(mesh), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(work() / "X.stl") || fs::exists(work() / "X.json")) << mesh;
  }
}

TEST_F(Cli, MissingOrBadPointsFailWithTheirNameAndNoOutput) {
  {
    std::ofstream bad(work() / "bad.xyz");
    bad << "0 0 0\n1 0 nan\n0 1 0\n";
    std::ofstream(work() / "empty.xyz");
  }
  for (const char* points : {"missing.xyz", "bad.xyz", "empty.xyz"}) {
    const Outcome o =
        run(std::string("--points ") + points + " --resolution 33 -o X.stl --report X.json --quiet");
    EXPECT_EQ(o.exit_code, 1) << points;
    expect_one_error_line(o);
    EXPECT_NE(o.err.find(points), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(work() / "X.stl") || fs::exists(work() / "X.json")) << points;
  }
  const Outcome route = run("--points bad.xyz --point-route magic -o X.stl");
  EXPECT_EQ(route.exit_code, 2);
  expect_one_error_line(route);
  const Outcome both = run("--points bad.xyz --mesh bunny.obj -o X.stl");
  EXPECT_EQ(both.exit_code, 2);
  expect_one_error_line(both);
}

// The band is estimated on a coarse grid before anything large is allocated: a run that would not fit
// is refused with the resolution that would (the sphere at N = 161 needs about 193 MiB).
TEST_F(Cli, RunThatWouldNotFitInMemoryIsRefusedBeforeRunning) {
  const Outcome o = run("--shape sphere --resolution 161 --max-memory 0.1 --quiet -o X.stl --report X.json");
  EXPECT_EQ(o.exit_code, 1);
  expect_one_error_line(o);
  EXPECT_NE(o.err.find("--max-memory"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("use --resolution"), std::string::npos) << o.err;
  EXPECT_TRUE(files_in_work().empty());
  const Outcome fits = run("--shape sphere --resolution 161 --max-memory 1 --max-steps 1 --quiet -o X.stl");
  EXPECT_EQ(fits.exit_code, 0) << fits.err;
}

// One estimate for the printout and the guard (issue 47: the printout said 863 MiB where the guard
// refused at "about 4.03 GB"): the figure the refusal names is the one printed before it.
TEST_F(Cli, MemoryGuardNamesThePrintedEstimate) {
  const Outcome o = run("--shape sphere --resolution 161 --max-memory 0.1 -o X.stl");
  EXPECT_EQ(o.exit_code, 1);
  const auto first_group = [](const std::string& text, const char* pattern) {
    std::smatch m;
    return std::regex_search(text, m, std::regex(pattern)) ? m[1].str() : std::string();
  };
  const std::string printed = first_group(o.out, R"(peak memory (\d+) MiB)");
  ASSERT_FALSE(printed.empty()) << o.out;
  EXPECT_EQ(printed, first_group(o.err, R"(needs about (\d+) MiB)")) << o.out << o.err;
  EXPECT_NE(o.err.find("0.1 GB"), std::string::npos) << o.err;
}

TEST_F(Cli, SolidZoneOptionsAreChecked) {
  const Outcome malformed = run(kSmallRun + " --keep-out 1,2,3 -o X.stl");
  EXPECT_EQ(malformed.exit_code, 2);
  expect_one_error_line(malformed);
  EXPECT_NE(malformed.err.find("X,Y,Z,R"), std::string::npos) << malformed.err;
  const Outcome reference = run(kSmallRun + " --rim 1 --solver reference -o X.stl");
  EXPECT_EQ(reference.exit_code, 1);
  expect_one_error_line(reference);
  EXPECT_TRUE(files_in_work().empty());
  const Outcome bad_box = run(kSmallRun + " --keep-out-box 0,0,0,1,1 -o X.stl");
  EXPECT_EQ(bad_box.exit_code, 2);
  expect_one_error_line(bad_box);
  const Outcome empty_box = run(kSmallRun + " --keep-out-box 0,0,0,1,-1,1 -o X.stl");
  EXPECT_EQ(empty_box.exit_code, 1);
  expect_one_error_line(empty_box);
  const Outcome no_ply = run(kSmallRun + " --keep-out-mask keepout -o X.stl");
  EXPECT_EQ(no_ply.exit_code, 1);
  expect_one_error_line(no_ply);
  EXPECT_NE(no_ply.err.find("PLY"), std::string::npos) << no_ply.err;
  EXPECT_TRUE(files_in_work().empty());
  const Outcome ok = run(kSmallRun + " --keep-out 0.5,0.5,0.8,0.1 -o X.stl");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// Issue 47: a request the run cannot honour is said even when quiet (on stderr; stdout stays empty): a
// keep-out 460 mm from a 20 mm sphere keeps nothing solid.
TEST_F(Cli, QuietRunsStillWarnOfRequestsThatTouchNothing) {
  const Outcome o =
      run("--shape sphere --radius 20 --resolution 41 --max-steps 3 --quiet --keep-out 460,0,0,5 -o X.stl");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  EXPECT_TRUE(o.out.empty()) << "--quiet prints nothing on stdout:\n" << o.out;
  EXPECT_NE(o.err.find("poreshell: warning: --keep-out 460,0,0,5 lies 435 mm outside the model's bounds"),
            std::string::npos)
      << o.err;
}

TEST_F(Cli, OutputInAMissingDirectoryFailsBeforeRunning) {
  const Outcome o = run(kSmallRun + " -o no-such-dir/X.stl --report X.json");
  EXPECT_EQ(o.exit_code, 1);
  expect_one_error_line(o);
  EXPECT_NE(o.err.find("does not exist"), std::string::npos) << o.err;
  EXPECT_TRUE(files_in_work().empty());
}

TEST_F(Cli, SmallRunWritesStlAndReport) {
  const Outcome o = run(kSmallRun + " -o X.stl --report X.json");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  EXPECT_TRUE(o.out.empty()) << "--quiet prints nothing on stdout:\n" << o.out;
  // 5 steps cannot reach tol 1e-12: the run succeeds but says so, quiet or not.
  EXPECT_NE(o.err.find("warning"), std::string::npos) << o.err;
  EXPECT_EQ(o.err.find("step "), std::string::npos) << "--quiet prints no progress:\n" << o.err;

  const std::string stl = read_file(work() / "X.stl");
  ASSERT_GE(stl.size(), 84u);
  const std::uint32_t triangles = stl_triangle_count(stl);
  EXPECT_GT(triangles, 0u);
  EXPECT_EQ(stl.size(), 84u + 50u * triangles);

  const nlohmann::json report = nlohmann::json::parse(read_file(work() / "X.json"));
  for (const char* key :
       {"/grid/dims", "/grid/h", "/band/voxels", "/band/ghosts", "/solver/name", "/solver/steps",
        "/solver/final_ec", "/solver/repeated_steps", "/solver/coarse_start", "/solver/energy/first",
        "/solver/energy/last", "/pattern/spots", "/pattern/size_cv", "/mesh/triangles", "/mesh/closed",
        "/mesh/manifold", "/mesh/euler_characteristic", "/seconds/total", "/threads"})
    EXPECT_TRUE(report.contains(nlohmann::json::json_pointer(key))) << key;
  EXPECT_EQ(report["grid"]["dims"], nlohmann::json({33, 33, 33}));
  EXPECT_EQ(report["solver"]["steps"], 5);
  EXPECT_TRUE(report["solver"]["coarse_start"].is_null());  // the paper's eps_4: the grid is the pattern's
  EXPECT_EQ(report["mesh"]["triangles"], triangles);
  EXPECT_EQ(report["mesh"]["closed"], true);
  EXPECT_EQ(report["mesh"]["manifold"], true);
  // What was asked: the command line as given, the version, every setting by its API name.
  const nlohmann::json& line = report["command_line"];
  ASSERT_TRUE(line.is_array() && line.size() > 4) << line;
  EXPECT_EQ(line.back(), "X.json");
  EXPECT_NE(std::find(line.begin(), line.end(), "--max-steps"), line.end());
  EXPECT_FALSE(report["version"].get<std::string>().empty());
  EXPECT_EQ(report["settings"]["max_steps"], 5);
  EXPECT_EQ(report["settings"]["seed"], 1);
  EXPECT_EQ(report["settings"]["offset"], "centered");
  EXPECT_EQ(report["settings"].size(), 43u) << "a new option needs its line in settings_json";
  EXPECT_TRUE(report["mesh"]["applied"]["rim_measured_mm"].is_null());  // a sphere has no boundary

  std::vector<std::string> names = files_in_work();
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"X.json", "X.stl"})) << "no temporary files left behind";
}

TEST_F(Cli, SummaryGivesTheEstimateAndNamesEachOutputUnlessQuiet) {
  std::string loud = kSmallRun;
  loud.erase(loud.find(" --quiet"), std::string(" --quiet").size());
  const Outcome o = run(loud + " --progress plain -o X.stl");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  EXPECT_NE(o.out.find("estimate"), std::string::npos) << "the cost before the run:\n" << o.out;
  EXPECT_NE(o.out.find("X.stl"), std::string::npos) << "the summary names each output:\n" << o.out;
  EXPECT_NE(o.err.find("step "), std::string::npos) << "plain progress prints steps:\n" << o.err;
}

TEST_F(Cli, SeveralIsoLevelsWriteSuffixedFiles) {
  const Outcome o = run(kSmallRun + " --iso 0.3,0 -o X.stl");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  EXPECT_TRUE(fs::exists(work() / "X-iso0.3.stl"));
  EXPECT_TRUE(fs::exists(work() / "X-iso0.stl"));
  EXPECT_FALSE(fs::exists(work() / "X.stl"));
}

TEST_F(Cli, ThreadCountDoesNotChangeTheOutput) {
  const Outcome one = run(kSmallRun + " --threads 1 -o one.stl --report one.json");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const Outcome two = run(kSmallRun + " --threads 2 -o two.stl --report two.json");
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const std::string a = read_file(work() / "one.stl"), b = read_file(work() / "two.stl");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "STL differs between --threads 1 and --threads 2";
  EXPECT_EQ(nlohmann::json::parse(read_file(work() / "one.json"))["threads"], 1);
}

TEST_F(Cli, OutputFormatFollowsTheExtensionAndUnknownOnesFailBeforeRunning) {
  for (const char* name : {"X.3mf", "X.obj", "X.ply"}) {
    const Outcome o = run(kSmallRun + " -o " + name);
    ASSERT_EQ(o.exit_code, 0) << name << ": " << o.err;
    EXPECT_GT(fs::file_size(work() / name), 1000u) << name;
  }
  const Outcome o = run("--resolution 131 -o X.vtk --report X.json");  // fails before the solve
  EXPECT_EQ(o.exit_code, 1);
  expect_one_error_line(o);
  EXPECT_NE(o.err.find(".stl, .3mf, .obj, .ply"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(work() / "X.vtk") || fs::exists(work() / "X.json"));
}

TEST_F(Cli, UnitsScaleTheOutputToMillimetresAndModesAreSelectable) {
  // The full isosurfaces (--max-deviation 0): a reduction's bound is in mm, whatever the input's unit.
  ASSERT_EQ(run(kSmallRun + " --max-deviation 0 -o mm.stl --report mm.json").exit_code, 0);
  ASSERT_EQ(run(kSmallRun + " --max-deviation 0 --units cm -o cm.stl --report cm.json").exit_code, 0);
  const auto mm = nlohmann::json::parse(read_file(work() / "mm.json"));
  const auto cm = nlohmann::json::parse(read_file(work() / "cm.json"));
  EXPECT_EQ(mm["units"]["input"], "mm");
  EXPECT_EQ(cm["units"]["input"], "cm");
  EXPECT_EQ(cm["units"]["output"], "mm");
  EXPECT_EQ(mm["solid"]["mode"], "shell");
  EXPECT_NEAR(cm["grid"]["h_mm"].get<double>() / mm["grid"]["h_mm"].get<double>(), 10.0, 1e-9);
  EXPECT_NEAR(cm["mesh"]["volume"].get<double>() / mm["mesh"]["volume"].get<double>(), 1000.0, 1e-6);

  const Outcome nv = run(kSmallRun + " --mode narrow-volume -o nv.stl --report nv.json");
  ASSERT_EQ(nv.exit_code, 0) << nv.err;
  EXPECT_EQ(nlohmann::json::parse(read_file(work() / "nv.json"))["solid"]["mode"], "narrow-volume");
  const Outcome bad = run(kSmallRun + " --mode narrow-volume --wall 1 -o bad.stl");
  EXPECT_EQ(bad.exit_code, 1);
  expect_one_error_line(bad);
  EXPECT_FALSE(fs::exists(work() / "bad.stl"));
}

}  // namespace

TEST_F(Cli, HoleSizeRequestsAreCheckedAndReported) {
  const std::string sphere = "--shape sphere --radius 10 --quiet";
  const Outcome wide = run(sphere + " --hole-diameter 9 --spacing 10 -o X.stl");
  EXPECT_EQ(wide.exit_code, 1);
  expect_one_error_line(wide);
  EXPECT_NE(wide.err.find("--hole-diameter 8 --spacing 10"), std::string::npos) << wide.err;
  const Outcome both = run(sphere + " --hole-diameter 3 --alpha 100 -o X.stl");
  EXPECT_EQ(both.exit_code, 2) << "the hole map sets alpha: asking for both is a usage error";
  expect_one_error_line(both);
  const Outcome ungraded = run(sphere + " --grade axis:z:2:4 -o X.stl");
  EXPECT_EQ(ungraded.exit_code, 1);
  EXPECT_NE(ungraded.err.find("--hole-diameter"), std::string::npos) << ungraded.err;
  const Outcome bad_grade = run(sphere + " --hole-diameter 3 --grade axis:q:2:4 -o X.stl");
  EXPECT_EQ(bad_grade.exit_code, 1);
  expect_one_error_line(bad_grade);
  const Outcome huge =
      run("--shape sphere --radius 50 --quiet --hole-diameter 0.6 --spacing 1 --max-memory 0.5 -o X.stl");
  EXPECT_EQ(huge.exit_code, 1);
  expect_one_error_line(huge);
  EXPECT_NE(huge.err.find("ask for holes and spacing"), std::string::npos) << huge.err;
  const Outcome coarse = run(sphere + " --hole-diameter 3 --spacing 5 --voxel-size 2 -o X.stl");
  EXPECT_EQ(coarse.exit_code, 1);
  EXPECT_NE(coarse.err.find("too coarse"), std::string::npos) << coarse.err;
  EXPECT_TRUE(files_in_work().empty());

  const Outcome ok =
      run(sphere + " --hole-diameter 3 --spacing 5 --wall 1 --max-steps 5 -o X.stl --report X.json");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const nlohmann::json report = nlohmann::json::parse(read_file(work() / "X.json"));
  EXPECT_EQ(report["holes"]["requested"]["diameter_mm"], 3.0);
  EXPECT_EQ(report["holes"]["planned"]["spacing_mm"], 5.0);
  for (const char* key : {"/model/alpha_per_mm2", "/model/epsilon_mm", "/model/h_mm", "/model/phi_bar",
                          "/mesh/holes/diameter_mean_mm", "/mesh/holes/diameter_cv",
                          "/mesh/holes/spacing_mean_mm", "/mesh/holes/spacing_cv", "/mesh/holes/porosity",
                          "/mesh/wall/requested_mm", "/mesh/wall/measured_median_mm"})
    EXPECT_TRUE(report.contains(nlohmann::json::json_pointer(key))) << key;
  EXPECT_NEAR(report["model"]["h_mm"].get<double>(),
              report["holes"]["planned"]["voxel_size_mm"].get<double>(),
              0.02 * report["model"]["h_mm"].get<double>());
  const nlohmann::json& wall = report["mesh"]["wall"];
  EXPECT_NEAR(wall["measured_median_mm"].get<double>(), 1.0, 0.1);
  // A sphere has no part thinner than two walls: every probe within the percentiles' few hundredths.
  EXPECT_LE(wall["measured_p5_mm"].get<double>(), wall["measured_median_mm"].get<double>());
  EXPECT_GE(wall["measured_p95_mm"].get<double>(), wall["measured_median_mm"].get<double>());
  EXPECT_LT(wall["measured_p95_mm"].get<double>() - wall["measured_p5_mm"].get<double>(), 0.1);
  EXPECT_EQ(wall["merged_probes"].get<int>(), 0);
}
