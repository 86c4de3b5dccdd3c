#include "viewer/html_viewer.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string_view>
#include <system_error>
#include <thread>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "poreshell/base64.hpp"
#include "viewer/viewer_assets.hpp"

extern char** environ;

namespace poreshell {
namespace {

// Little-endian bytes of 32-bit values, whatever the host's order (the page reads them with typed
// arrays, which are little-endian on every browser platform).
void append_u32(std::string& bytes, std::uint32_t v) {
  for (int shift = 0; shift < 32; shift += 8) bytes.push_back(static_cast<char>((v >> shift) & 0xffu));
}
void append_f32(std::string& bytes, double v) {
  const auto f = static_cast<float>(v);
  std::uint32_t u = 0;
  static_assert(sizeof f == sizeof u);
  std::memcpy(&u, &f, sizeof u);
  append_u32(bytes, u);
}
void append_f32(std::string& bytes, const Vec3& v) {
  for (int i = 0; i < 3; ++i) append_f32(bytes, v[i]);
}

bool finite(const Vec3& v) {
  return v.allFinite();
}

void check(const ViewerData& data) {
  const TriangleMesh& mesh = data.mesh;
  if (mesh.triangles.size() > html_viewer_max_triangles)
    throw InputError("the viewer's mesh has " + std::to_string(mesh.triangles.size()) + " triangles, over " +
                     std::to_string(html_viewer_max_triangles) + ": reduce it for display first");
  for (const Vec3& v : mesh.vertices)
    if (!finite(v)) throw InputError("the viewer's mesh has a non-finite vertex coordinate");
  for (const auto& t : mesh.triangles)
    for (const std::int32_t i : t)
      if (i < 0 || static_cast<std::size_t>(i) >= mesh.vertices.size())
        throw InputError("the viewer's mesh has a vertex index out of range: " + std::to_string(i));
  for (const ViewerHole& h : data.holes)
    if (!finite(h.centre) || !finite(h.normal) || !std::isfinite(h.diameter_mm))
      throw InputError("a hole for the viewer has a non-finite centre, normal or diameter");
  if (!data.pattern.empty() && data.pattern.size() != mesh.vertices.size())
    throw InputError("the viewer's pattern has " + std::to_string(data.pattern.size()) + " values for " +
                     std::to_string(mesh.vertices.size()) + " vertices");
  if (!(data.density_g_per_cm3 > 0.0)) throw InputError("the viewer's density must be positive (g/cm^3)");
}

nlohmann::json page_data(const ViewerData& data) {
  using nlohmann::json;
  std::string positions, indices, holes;
  positions.reserve(12 * data.mesh.vertices.size());
  for (const Vec3& v : data.mesh.vertices) append_f32(positions, v);
  indices.reserve(12 * data.mesh.triangles.size());
  for (const auto& t : data.mesh.triangles)
    for (const std::int32_t i : t) append_u32(indices, static_cast<std::uint32_t>(i));
  std::string pattern;
  pattern.reserve(4 * data.pattern.size());
  for (const float p : data.pattern) append_f32(pattern, p);
  // Eleven floats a hole, in the order viewer.js reads them.
  for (const ViewerHole& h : data.holes) {
    append_f32(holes, h.centre);
    append_f32(holes, h.normal);
    append_f32(holes, h.diameter_mm);
    append_f32(holes, h.circularity);
    append_f32(holes, h.nearest_neighbour_mm);
    append_f32(holes, h.axis_ratio);
    append_f32(holes, h.asked_mm);
  }
  json spheres = json::array(), boxes = json::array(), rims = json::array();
  for (const ViewerSphere& s : data.keep_out_spheres)
    spheres.push_back({s.centre.x(), s.centre.y(), s.centre.z(), s.radius_mm});
  for (const ViewerBox& b : data.keep_out_boxes)
    boxes.push_back({b.min.x(), b.min.y(), b.min.z(), b.max.x(), b.max.y(), b.max.z()});
  for (const std::vector<Vec3>& loop : data.rim_loops) {
    std::string points;
    for (const Vec3& p : loop) append_f32(points, p);
    rims.push_back(base64_encode(points));
  }
  static constexpr std::string_view axes = "xyz";
  return {{"format", 1},
          {"title", data.title},
          {"up_axis", std::string(1, axes[static_cast<std::size_t>(std::clamp(data.up_axis, 0, 2))])},
          {"requested_diameter_mm",
           data.requested_diameter_mm ? json(*data.requested_diameter_mm) : json(nullptr)},
          {"density_g_per_cm3", data.density_g_per_cm3},
          {"mesh",
           {{"vertices", data.mesh.vertices.size()},
            {"triangles", data.mesh.triangles.size()},
            {"positions", base64_encode(positions)},
            {"indices", base64_encode(indices)},
            {"pattern", data.pattern.empty() ? json(nullptr) : json(base64_encode(pattern))}}},
          {"holes", {{"count", data.holes.size()}, {"data", base64_encode(holes)}}},
          {"rim_width_mm", data.rim_width_mm},
          {"rim_loops", rims},
          {"keep_out_spheres", spheres},
          {"keep_out_boxes", boxes},
          {"report", data.report}};
}

void replace_all(std::string& text, std::string_view from, std::string_view to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

// Script text inside <script>: "</script" would end it early.
std::string script_text(std::string_view js) {
  std::string text(js);
  replace_all(text, "</script", "<\\/script");
  replace_all(text, "<!--", "<\\!--");
  return text;
}

std::string html_escape(std::string_view s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out.push_back(c);
    }
  }
  return out;
}

// Replaces the one marker `name` in `page` by `value`.
void fill(std::string& page, std::string_view name, const std::string& value) {
  const std::size_t at = page.find(name);
  if (at == std::string::npos) throw std::logic_error("viewer template lacks " + std::string(name));
  page.replace(at, name.size(), value);
}

}  // namespace

std::string html_viewer_page(const ViewerData& data) {
  check(data);
  // The JSON as a script's text: every '<' escaped (it can only stand in strings) so that nothing in
  // a title or a path can close the element.
  std::string json = page_data(data).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  replace_all(json, "<", "\\u003c");
  std::string scripts;
  scripts.reserve(json.size() + embedded::three_js.size() + 100'000);
  scripts += "<script>\n" + script_text(embedded::three_js) + "\n</script>\n";
  scripts += "<script>\n" + script_text(embedded::orbit_controls_js) + "\n</script>\n";
  scripts += "<script type=\"application/json\" id=\"poreshell-data\">" + json + "</script>\n";
  scripts += "<script>\n" + script_text(embedded::viewer_js) + "\n</script>";

  std::string page(embedded::viewer_html);
  const std::string title = html_escape(data.title);
  fill(page, "@TITLE@", title);
  fill(page, "@TITLE@", title);
  fill(page, "@STYLE@", std::string(embedded::viewer_css));
  fill(page, "@SCRIPTS@", scripts);
  return page;
}

void write_html_viewer(const std::filesystem::path& path, const ViewerData& data) {
  const std::string page = html_viewer_page(data);
  write_atomically(
      path, [&](std::ostream& out) { out.write(page.data(), static_cast<std::streamsize>(page.size())); });
}

std::optional<std::filesystem::path> find_chromium(const std::filesystem::path& chromium) {
  namespace fs = std::filesystem;
  const auto executable = [](const fs::path& p) { return !p.empty() && ::access(p.c_str(), X_OK) == 0; };
  if (!chromium.empty()) return executable(chromium) ? std::optional(chromium) : std::nullopt;
  if (const char* env = std::getenv("PORESHELL_CHROMIUM"); env && *env)
    return executable(env) ? std::optional(fs::path(env)) : std::nullopt;
  const char* path_env = std::getenv("PATH");
  const std::string path = path_env ? path_env : "/usr/local/bin:/usr/bin:/bin";
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    std::size_t begin = 0;
    while (begin <= path.size()) {
      const std::size_t end = std::min(path.find(':', begin), path.size());
      const fs::path candidate = fs::path(path.substr(begin, end - begin)) / name;
      if (end > begin && executable(candidate)) return candidate;
      begin = end + 1;
    }
  }
  return std::nullopt;
}

namespace {

// file:// URL of an absolute path, bytes outside the unreserved set percent-encoded.
std::string file_url(const std::filesystem::path& path) {
  static constexpr char hex[] = "0123456789ABCDEF";
  std::string url = "file://";
  for (const char c : std::filesystem::absolute(path).lexically_normal().string()) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      url.push_back(c);
    } else {
      url.push_back('%');
      url.push_back(hex[u >> 4]);
      url.push_back(hex[u & 15u]);
    }
  }
  return url;
}

// A fresh directory for Chromium's profile, removed when done.
struct TemporaryDirectory {
  std::filesystem::path path;
  TemporaryDirectory() {
    std::random_device random;
    const auto base = std::filesystem::temp_directory_path();
    for (int attempt = 0; attempt < 100; ++attempt) {
      path = base / ("poreshell-chromium-" + std::to_string(random()));
      if (std::filesystem::create_directory(path)) return;
    }
    throw std::runtime_error("cannot make a temporary directory in " + base.string());
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
};

}  // namespace

void render_html_png(const std::filesystem::path& html, const std::filesystem::path& png,
                     const PngOptions& options) {
  namespace fs = std::filesystem;
  const std::optional<fs::path> chromium = find_chromium(options.chromium);
  if (!chromium)
    throw InputError(
        "rendering a PNG needs Chromium, which was not found" +
        (options.chromium.empty() ? std::string() : " at " + options.chromium.string()) +
        ": install it (apt-get install chromium, or scripts/install-deps) or set PORESHELL_CHROMIUM");
  if (!fs::is_regular_file(html)) throw InputError("no such page: " + html.string());
  if (options.width < 16 || options.height < 16 || options.width > 8192 || options.height > 8192)
    throw InputError("the PNG's size must be 16 to 8192 pixels a side");

  const TemporaryDirectory profile;
  const fs::path temporary = profile.path / "page.png";
  const fs::path log = profile.path / "chromium.log";
  std::vector<std::string> args = {
      chromium->string(), "--headless", "--hide-scrollbars", "--no-first-run", "--no-default-browser-check",
      "--disable-extensions", "--disable-background-networking", "--mute-audio",
      // Software WebGL: headless machines have no GPU.
      "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--user-data-dir=" + profile.path.string(),
      "--window-size=" + std::to_string(options.width) + "," + std::to_string(options.height),
      // Lets the page's script run to its first frame before the screenshot.
      "--virtual-time-budget=5000", "--screenshot=" + temporary.string(), file_url(html)};
  if (::geteuid() == 0) args.insert(args.begin() + 1, "--no-sandbox");  // Chromium refuses root otherwise
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);  // its own group: a timeout ends all of it
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (spawned != 0)
    throw std::runtime_error("cannot start " + chromium->string() + ": " + std::strerror(spawned));

  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(options.timeout_seconds);
  while (true) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR)
      throw std::runtime_error("waiting for chromium: " + std::string(std::strerror(errno)));
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      throw std::runtime_error("chromium took over " + std::to_string(options.timeout_seconds) +
                               " s to render " + html.string());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(-pid, SIGKILL);  // helpers it may have left behind
  std::string signature(8, '\0');
  std::ifstream(temporary, std::ios::binary).read(signature.data(), 8);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || signature != "\x89PNG\r\n\x1a\n") {
    std::ifstream in(log);
    std::string tail((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (tail.size() > 600) tail = "..." + tail.substr(tail.size() - 600);
    throw std::runtime_error("chromium did not render " + html.string() + " (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + "): " + tail);
  }
  // Into place atomically: a copy next to the target, then a rename.
  write_atomically(png,
                   [&](std::ostream& out) { out << std::ifstream(temporary, std::ios::binary).rdbuf(); });
}

}  // namespace poreshell
