// The studio's HTTP API (docs/studio.md), its server in this process on a free port: every route, and
// each refusal of "Safety" (no token, a wrong one, a foreign Host, a path out of a job, an upload over
// the limit, a bad option, a second job, a malformed upload), on a small sphere so that it takes seconds.

#include <gtest/gtest.h>
#include <httplib.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "poreshell/base64.hpp"
#include "server.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// An icosphere of radius `r` mm as OBJ text (642 vertices at 3 subdivisions).
std::string sphere_obj(double r, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<std::array<double, 3>> v{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                       {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                       {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> middle;
    const auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (const auto it = middle.find(key); it != middle.end()) return it->second;
      v.push_back({(v[a][0] + v[b][0]) / 2, (v[a][1] + v[b][1]) / 2, (v[a][2] + v[b][2]) / 2});
      return middle[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& [a, b, c] : f) {
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    f = std::move(next);
  }
  std::ostringstream obj;
  for (const auto& p : v) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    obj << "v " << p[0] / n * r << ' ' << p[1] / n * r << ' ' << p[2] / n * r << '\n';
  }
  for (const auto& [a, b, c] : f) obj << "f " << a + 1 << ' ' << b + 1 << ' ' << c + 1 << '\n';
  return obj.str();
}

constexpr std::size_t kUploadLimit = 200 * 1024;  // small, so that the 413 costs little

class Studio : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    workdir_ =
        fs::temp_directory_path() / (std::string("poreshell-test-studio-") + std::to_string(::getpid()));
    fs::create_directories(workdir_);
    studio::ServerConfig config;
    config.workdir = workdir_;
    config.upload_limit = kUploadLimit;
    server_ = new studio::Server(config);
    port_ = server_->bind();
    thread_ = new std::thread([] { server_->run(); });
  }
  static void TearDownTestSuite() {
    server_->stop();
    thread_->join();
    delete thread_;
    delete server_;
    fs::remove_all(workdir_);
  }

  // A client that sends the token as a header and this studio's Host.
  static httplib::Client client() {
    httplib::Client c("127.0.0.1", port_);
    c.set_default_headers({{"X-Poreshell-Token", server_->token()}});
    c.set_read_timeout(60);
    return c;
  }
  static json body(const httplib::Result& r) { return json::parse(r->body, nullptr, false); }
  static json upload(const std::string& name, const std::string& bytes, int expected_status) {
    auto r =
        client().Post(("/api/model?name=" + name + "&units=mm").c_str(), bytes, "application/octet-stream");
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, expected_status) << r->body;
    return body(r);
  }
  // A fresh upload each time: the studio keeps its last three models.
  static int sphere_model() { return upload("ball.obj", sphere_obj(20.0, 3), 200)["id"].get<int>(); }
  static json wait_done(int job) {
    for (int i = 0; i < 600; ++i) {
      auto r = client().Get(std::string("/api/jobs/") + std::to_string(job));
      const json s = body(r);
      if (s["state"] != "queued" && s["state"] != "running") return s;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return {};
  }

  static inline fs::path workdir_;
  static inline studio::Server* server_ = nullptr;
  static inline std::thread* thread_ = nullptr;
  static inline int port_ = 0;
};

const std::string kOptions = R"("options": {"hole_diameter": 6, "spacing": 10})";

TEST_F(Studio, TokenIsRequiredByHeaderQueryOrCookie) {
  const std::string token = server_->token();
  EXPECT_GE(token.size(), 32u);  // 128 bits or more, in hex
  httplib::Client bare("127.0.0.1", port_);
  EXPECT_EQ(bare.Get("/api/health")->status, 403);
  EXPECT_EQ(bare.Get("/api/health", {{"X-Poreshell-Token", token + "0"}})->status, 403);
  EXPECT_EQ(bare.Get("/api/health?token=" + std::string(token.size(), 'a'))->status, 403);
  EXPECT_EQ(bare.Get("/")->status, 403);
  EXPECT_EQ(bare.Get(std::string("/api/health?token=") + token)->status, 200);
  EXPECT_EQ(bare.Get("/api/health", {{"Cookie", std::string("a=b; poreshell_token=") + token}})->status, 200);
  const auto health = client().Get("/api/health");
  ASSERT_EQ(health->status, 200);
  EXPECT_TRUE(body(health).contains("version"));
}

TEST_F(Studio, ForeignHostIsRefused) {
  auto c = client();
  const std::string port = std::string(":") + std::to_string(port_);
  for (const std::string& host : std::vector<std::string>{
           std::string("localhost") + port, std::string("127.0.0.1") + port, std::string("[::1]") + port})
    EXPECT_EQ(c.Get("/api/health", {{"Host", host}})->status, 200) << host;
  for (const std::string& host :
       std::vector<std::string>{std::string("evil.example") + port, "localhost", "127.0.0.1:1",
                                std::string("localhost.evil") + port})
    EXPECT_EQ(c.Get("/api/health", {{"Host", host}})->status, 403) << host;
}

TEST_F(Studio, PageSetsTheCookieAndNeedsNoNetwork) {
  httplib::Client bare("127.0.0.1", port_);
  const auto page = bare.Get(std::string("/?token=") + server_->token());
  ASSERT_EQ(page->status, 200);
  EXPECT_NE(page->get_header_value("Set-Cookie").find(std::string("poreshell_token=") + server_->token()),
            std::string::npos);
  EXPECT_NE(page->get_header_value("Set-Cookie").find("HttpOnly"), std::string::npos);
  EXPECT_NE(page->body.find("<html"), std::string::npos);
  EXPECT_EQ(page->body.find("src=\"http"), std::string::npos);
  EXPECT_EQ(page->body.find("href=\"http"), std::string::npos);
  const auto options = client().Get("/api/options");
  ASSERT_EQ(options->status, 200);
  EXPECT_TRUE(body(options)["options"].is_array());
  EXPECT_EQ(body(options)["defaults"]["crease_angle"], 40.0);
}

TEST_F(Studio, UploadsAreCheckedAndStoredUnderTheStudiosNames) {
  const json model = upload("../../evil/ball.obj", sphere_obj(20.0, 2), 200);
  EXPECT_EQ(model["vertices"], 162);
  EXPECT_NEAR(model["size_mm"][0].get<double>(), 40.0, 0.5);
  EXPECT_FALSE(fs::exists(workdir_ / ".." / "evil"));
  for (const auto& entry : fs::directory_iterator(workdir_ / "models"))
    EXPECT_EQ(entry.path().filename().string().rfind("model-", 0), 0u) << entry.path();
  upload("ball.exe", "v 0 0 0\n", 400);                           // not a model's extension
  upload("ball.stl", std::string(300, '\x07'), 400);              // malformed: the reader refuses it
  upload("ball.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n", 400);         // a face out of range
  upload("big.obj", std::string(kUploadLimit + 1000, ' '), 413);  // over the limit
  EXPECT_EQ(client().Post("/api/model?name=a.obj&units=furlong", "v 0 0 0\n", "text/plain")->status, 400);
  EXPECT_EQ(client().Get("/api/model/999")->status, 404);
}

TEST_F(Studio, PreviewGivesHolesAndCentresAndKeepsOutWhereAsked) {
  const int id = sphere_model();
  const auto r =
      client().Post("/api/preview", std::string("{\"model\": ") + std::to_string(id) + ", " + kOptions + "}",
                    "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  const json p = body(r);
  ASSERT_GT(p["holes"].get<int>(), 10);
  ASSERT_EQ(p["centres"].size(), p["holes"].get<std::size_t>());
  EXPECT_GT(p["figures"]["porosity"].get<double>(), 0.0);
  EXPECT_TRUE(p["surface"]["positions"].is_string());
  // The page names the surface it shows: a preview on the same split sends the pattern alone, one on
  // another surface the whole of it.
  json again = json::parse(std::string("{\"model\": ") + std::to_string(id) + ", " + kOptions + "}");
  again["options"]["seed"] = 7;
  again["surface_id"] = p["surface"]["id"];
  const json same = body(client().Post("/api/preview", again.dump(), "application/json"));
  EXPECT_EQ(same["surface"]["id"], p["surface"]["id"]);
  EXPECT_FALSE(same["surface"].contains("positions"));
  EXPECT_TRUE(same["surface"]["pattern"].is_string());
  again["surface_id"] = "some-other-surface";
  EXPECT_TRUE(body(client().Post("/api/preview", again.dump(), "application/json"))["surface"]["positions"]
                  .is_string());
  // Graded along z from 4 to 8 mm: the smallest holes low, the largest high.
  const json graded = body(client().Post(
      "/api/preview",
      R"({"options": {"hole_diameter": 6, "spacing": 10, "grade": {"kind": "axis", "axis": 2, "from_diameter": 4, "to_diameter": 8}}})",
      "application/json"));
  ASSERT_GT(graded["holes"].get<int>(), 2) << graded.dump().substr(0, 300);
  double low = 0, high = 0;
  int lows = 0, highs = 0;
  for (std::size_t i = 0; i < graded["centres"].size(); ++i) {
    const double z = graded["centres"][i][2].get<double>(), d = graded["diameters"][i].get<double>();
    if (z < -10) {
      low += d;
      ++lows;
    } else if (z > 10) {
      high += d;
      ++highs;
    }
  }
  ASSERT_TRUE(lows > 0 && highs > 0);
  EXPECT_GT(high / highs, low / lows + 1.0) << "low " << low / lows << " high " << high / highs;
  // A keep-out over the +z cap and a painted -z cap: no hole centre in either.
  const std::string body_text =
      R"({"options": {"hole_diameter": 6, "spacing": 10, "keep_out": [[0, 0, 20, 12]]}})";
  const json k = body(client().Post("/api/preview", body_text, "application/json"));
  ASSERT_GT(k["holes"].get<int>(), 0);
  for (const json& c : k["centres"]) {
    const double dz = c[2].get<double>() - 20.0;
    EXPECT_GT(std::sqrt(c[0].get<double>() * c[0].get<double>() + c[1].get<double>() * c[1].get<double>() +
                        dz * dz),
              12.0);
  }
}

TEST_F(Studio, PaintedMaskKeepsItsAreaSolid) {
  // The mask is per vertex of the model as the upload's answer lists them (the reader's order, which
  // need not be the file's).
  const json model = upload("ball.obj", sphere_obj(20.0, 3), 200);
  const int id = model["id"].get<int>();
  const std::string positions = *poreshell::base64_decode(model["mesh"]["positions"].get<std::string>());
  ASSERT_EQ(positions.size(), model["vertices"].get<std::size_t>() * 12);
  json mask = json::array();
  for (std::size_t v = 0; v < positions.size() / 12; ++v) {
    float z = 0;
    std::memcpy(&z, positions.data() + v * 12 + 8, sizeof z);
    mask.push_back(z < -8.0f ? 1 : 0);
  }
  json request = {
      {"model", id}, {"options", {{"hole_diameter", 6}, {"spacing", 10}}}, {"keep_out_mask_values", mask}};
  const auto r = client().Post("/api/preview", request.dump(), "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  const json p = body(r);
  ASSERT_GT(p["holes"].get<int>(), 0);
  for (const json& c : p["centres"]) EXPECT_GT(c[2].get<double>(), -8.0);
  request["keep_out_mask_values"] = json::array({1, 0});
  const auto bad = client().Post("/api/preview", request.dump(), "application/json");
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(body(bad)["option"], "keep_out_mask_values");
}

TEST_F(Studio, BadOptionsAndBodiesGet400NamingTheOption) {
  sphere_model();
  auto c = client();
  const auto bad = c.Post("/api/preview", R"({"options": {"hole_diameter": -3}})", "application/json");
  ASSERT_EQ(bad->status, 400);
  EXPECT_EQ(body(bad)["option"], "hole_diameter");
  EXPECT_NE(body(bad)["error"].get<std::string>().find("hole_diameter"), std::string::npos);
  EXPECT_EQ(
      body(c.Post("/api/preview", R"({"options": {"no_such_option": 1}})", "application/json"))["option"],
      "no_such_option");
  EXPECT_EQ(c.Post("/api/preview", "{not json", "application/json")->status, 400);
  EXPECT_EQ(c.Post("/api/make", R"({"options": {"wall": "thick"}})", "application/json")->status, 400);
  EXPECT_EQ(c.Post("/api/preview", R"({"model": 12345, "options": {}})", "application/json")->status, 400);
}

TEST_F(Studio, MakeRunsOneJobStreamsProgressAndServesOnlyItsFiles) {
  const int id = sphere_model();
  auto c = client();
  const std::string request = std::string("{\"model\": ") + std::to_string(id) + ", " + kOptions + "}";
  const auto made = c.Post("/api/make", request, "application/json");
  ASSERT_EQ(made->status, 200) << made->body;
  const int job = body(made)["job"].get<int>();
  const auto second = c.Post("/api/make", request, "application/json");
  EXPECT_EQ(second->status, 409);  // one full job at a time

  // The event stream: data lines with fractions, the last one the finished state.
  std::string stream;
  const auto events = client().Get(std::string("/api/jobs/") + std::to_string(job) + "/events",
                                   [&](const char* data, std::size_t n) {
                                     stream.append(data, n);
                                     return true;
                                   });
  ASSERT_TRUE(events);
  EXPECT_EQ(events->get_header_value("Content-Type"), "text/event-stream");
  const std::size_t last = stream.rfind("data: ");
  ASSERT_NE(last, std::string::npos) << stream;
  EXPECT_EQ(json::parse(stream.substr(last + 6))["state"], "done") << stream;

  const json s = wait_done(job);
  ASSERT_EQ(s["state"], "done") << s.dump();
  EXPECT_EQ(s["files"], json::array({"part.3mf", "part.stl", "report.json", "holes.csv"}));
  const json& mesh = s["report"]["mesh"];
  EXPECT_TRUE(mesh["closed"].get<bool>() && mesh["manifold"].get<bool>()) << mesh.dump();
  EXPECT_EQ(mesh["parts"]["count"], 1);
  EXPECT_FALSE(mesh["hole_table"].empty());
  const std::string base = std::string("/api/jobs/") + std::to_string(job) + "/files/";
  for (const char* name : {"part.3mf", "part.stl", "report.json", "holes.csv"}) {
    const auto f = c.Get(base + name);  // NOLINT
    ASSERT_EQ(f->status, 200) << name;
    EXPECT_EQ(f->body.size(), fs::file_size(workdir_ / "jobs" / std::to_string(job) / name)) << name;
  }
  for (const char* name : {"..%2F..%2Fmodels%2Fmodel-1.obj", "../report.json", "%2Fetc%2Fpasswd",
                           "part.3mf%00", "part.3mf/..", "PART.3MF", "..", "report.json%2F"})
    EXPECT_EQ(c.Get(base + name)->status, 404) << name;
  EXPECT_EQ(c.Get("/api/jobs/99/files/part.3mf")->status, 404);
  EXPECT_EQ(c.Get("/api/jobs/99")->status, 404);
}

TEST_F(Studio, CancelAndADisconnectingClientLeaveTheServerWell) {
  const int id = sphere_model();
  auto c = client();
  const auto made =
      c.Post("/api/make", std::string("{\"model\": ") + std::to_string(id) + ", " + kOptions + "}",
             "application/json");
  ASSERT_EQ(made->status, 200) << made->body;
  const int job = body(made)["job"].get<int>();
  // A client that reads one event and hangs up.
  const auto cut = client().Get(std::string("/api/jobs/") + std::to_string(job) + "/events",
                                [](const char*, std::size_t) { return false; });
  EXPECT_FALSE(cut);
  EXPECT_EQ(c.Get("/api/health")->status, 200);
  const auto cancelled = c.Delete(std::string("/api/jobs/") + std::to_string(job));
  ASSERT_EQ(cancelled->status, 200);
  const json s = wait_done(job);
  EXPECT_TRUE(s["state"] == "cancelled" || s["state"] == "done") << s.dump();  // it may finish first
  if (s["state"] == "cancelled") {
    EXPECT_FALSE(fs::exists(workdir_ / "jobs" / std::to_string(job)));
  }
  EXPECT_EQ(c.Get("/api/health")->status, 200);
}

}  // namespace

namespace {

// The program itself: its first line is the address, and SIGTERM during a job stops it cleanly, the
// job's files removed and the temporary work folder with them.
TEST(StudioProgram, PrintsItsAddressAndStopsCleanlyOnSigterm) {
  const fs::path work =
      fs::temp_directory_path() / ("poreshell-test-studio-exe-" + std::to_string(::getpid()));
  fs::remove_all(work);
  int out[2];
  ASSERT_EQ(::pipe(out), 0);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, out[0]);
  const std::string dir = work.string();
  const char* argv[] = {PORESHELL_EXE, "studio",    "--no-browser", "--port",
                        "0",           "--workdir", dir.c_str(),    nullptr};
  pid_t pid = 0;
  ASSERT_EQ(::posix_spawn(&pid, PORESHELL_EXE, &actions, nullptr, const_cast<char* const*>(argv), environ),
            0);
  posix_spawn_file_actions_destroy(&actions);
  ::close(out[1]);
  std::string line;
  for (char c; ::read(out[0], &c, 1) == 1 && c != '\n';) line.push_back(c);
  ::close(out[0]);
  const std::string prefix = "studio: http://127.0.0.1:";
  ASSERT_EQ(line.rfind(prefix, 0), 0u) << line;
  const std::size_t slash = line.find("/?token=");
  ASSERT_NE(slash, std::string::npos) << line;
  const int port = std::stoi(line.substr(prefix.size(), slash - prefix.size()));
  const std::string token = line.substr(slash + 8);
  EXPECT_GE(token.size(), 32u);

  httplib::Client c("127.0.0.1", port);
  c.set_default_headers({{"X-Poreshell-Token", token}});
  ASSERT_EQ(c.Post("/api/model?name=ball.obj", sphere_obj(20.0, 3), "text/plain")->status, 200);
  const auto made =
      c.Post("/api/make", R"({"options": {"hole_diameter": 4, "spacing": 7}})", "application/json");
  ASSERT_EQ(made->status, 200) << made->body;
  ::kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_TRUE(fs::is_empty(work / "jobs"));  // the cancelled job left nothing
  fs::remove_all(work);
}

}  // namespace

namespace {

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A project (the model embedded, a keep-out, a painted cap) run by `poreshell --project` writes the
// same 3MF, byte for byte, as the studio's Make of the same request.
TEST_F(Studio, ProjectThroughTheCommandLineGivesMakesBytes) {
  const std::string obj = sphere_obj(20.0, 3);
  const json model = upload("ball.obj", obj, 200);
  const std::string positions = *poreshell::base64_decode(model["mesh"]["positions"].get<std::string>());
  json mask = json::array();
  for (std::size_t v = 0; v < positions.size() / 12; ++v) {
    float z = 0;
    std::memcpy(&z, positions.data() + v * 12 + 8, sizeof z);
    mask.push_back(z < -12.0f ? 1 : 0);
  }
  const json options = {{"hole_diameter", 6}, {"spacing", 10}, {"keep_out", {{0, 20, 0, 8}}}};
  const json request = {{"model", model["id"]}, {"options", options}, {"keep_out_mask_values", mask}};
  const auto made = client().Post("/api/make", request.dump(), "application/json");
  ASSERT_EQ(made->status, 200) << made->body;
  const int job = body(made)["job"].get<int>();
  ASSERT_EQ(wait_done(job)["state"], "done");
  const std::string part = read_bytes(workdir_ / "jobs" / std::to_string(job) / "part.3mf");
  ASSERT_GT(part.size(), 1000u);

  const fs::path project = workdir_ / "p.json", out = workdir_ / "cli.3mf";
  const json file = {
      {"poreshell_project", 1},
      {"model", {{"name", "ball.obj"}, {"units", "mm"}, {"data", poreshell::base64_encode(obj)}}},
      {"options", options},
      {"keep_out_mask_values", mask}};
  std::ofstream(project) << file.dump();
  const std::string command = std::string("'") + PORESHELL_EXE + "' --project '" + project.string() +
                              "' -o '" + out.string() + "' -q";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_TRUE(read_bytes(out) == part) << read_bytes(out).size() << " bytes against " << part.size();
}

}  // namespace
