// `poreshell studio [MODEL] [--units U] [--scale F] [--port N] [--host ADDR] [--no-browser] [--workdir DIR]`:
// prints the page's address, opens it, and serves until SIGINT or SIGTERM.

#include <fmt/core.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <thread>

#include "models.hpp"
#include "server.hpp"
#include "studio.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;

struct StudioCommand {
  std::string model, units = "mm", host = "127.0.0.1", workdir;
  double scale = 1.0;
  int port = 0;
  double upload_limit_mb = 500.0;
  bool no_browser = false;
};

// The default browser, through xdg-open; a machine without one just has the printed address.
void open_browser(const std::string& url) {
  pid_t pid = 0;
  const char* argv[] = {"xdg-open", url.c_str(), nullptr};
  if (::posix_spawnp(&pid, "xdg-open", nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0)
    return;
  std::thread([pid] { ::waitpid(pid, nullptr, 0); }).detach();
}

// The work folder: --workdir (kept), or a new temporary one (removed at the end).
fs::path make_workdir(const std::string& asked) {
  if (!asked.empty()) {
    fs::create_directories(asked);
    return fs::absolute(asked);
  }
  std::string pattern = (fs::temp_directory_path() / "poreshell-studio-XXXXXX").string();
  if (!::mkdtemp(pattern.data())) throw std::runtime_error("cannot make a work folder in " + pattern);
  return pattern;
}

}  // namespace

int studio_main(int argc, char** argv) {
  StudioCommand c;
  CLI::App app{"poreshell studio: the browser front end, served on this machine (docs/studio.md)",
               "poreshell studio"};
  app.add_option("model", c.model, "a model to open (STL, OBJ, PLY, OFF, 3MF, XYZ)")->type_name("MODEL");
  app.add_option("--units", c.units, "the model's units: m, cm, mm, inch")
      ->check(CLI::IsMember({"m", "cm", "mm", "inch"}));
  app.add_option("--scale", c.scale, "the model's initial scale")->check(CLI::PositiveNumber);
  app.add_option("--port", c.port, "port to listen on; 0 picks a free one")->check(CLI::Range(0, 65535));
  auto* host =
      app.add_option("--host", c.host, "address to listen on (default 127.0.0.1: this machine only)");
  app.add_flag("--no-browser", c.no_browser, "do not open the page, only print its address");
  app.add_option("--workdir", c.workdir,
                 "folder for uploads and jobs' files (default: a temporary one, removed at the end)");
  app.add_option("--upload-limit", c.upload_limit_mb, "largest upload, MB")->check(CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (host->count() > 0 && c.host != "127.0.0.1" && c.host != "localhost")
    fmt::print(stderr,
               "poreshell studio: warning: listening on {}: other machines that reach it can use the studio "
               "with the token\n",
               c.host);

  // SIGINT and SIGTERM go to one thread that stops the server; the others never see them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  const fs::path workdir = make_workdir(c.workdir);
  const bool temporary = c.workdir.empty();
  int status = 0;
  {
    studio::ServerConfig config;
    config.host = c.host;
    config.port = c.port;
    config.workdir = workdir;
    config.upload_limit = static_cast<std::size_t>(c.upload_limit_mb * 1024.0 * 1024.0);
    studio::Server server(config);
    if (!c.model.empty()) server.open_model(c.model, c.units);
    server.set_scale(c.scale);
    const int port = server.bind();
    const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/?token=" + server.token();
    fmt::print("studio: {}\n", url);
    std::fflush(stdout);
    if (!c.no_browser) open_browser(url);

    std::thread waiter([&] {
      int signal_number = 0;
      sigwait(&stop_signals, &signal_number);
      server.stop();
    });
    if (!server.run()) status = 1;
    ::kill(::getpid(), SIGTERM);  // wakes the waiter when serving ended by itself; harmless after a signal
    waiter.join();
    server.stop();
  }
  if (temporary) {
    std::error_code ignored;
    fs::remove_all(workdir, ignored);
  }
  fmt::print(stderr, "poreshell studio: stopped\n");
  return status;
}
