#pragma once
// The studio's HTTP server: the page and the API of docs/studio.md, on one port, guarded by the Host
// check and the token. The library runs in this process.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

namespace studio {

struct ServerConfig {
  std::string host = "127.0.0.1";
  int port = 0;                                       // 0: a free one
  std::filesystem::path workdir;                      // must exist; uploads and jobs' files go below it
  std::size_t upload_limit = std::size_t{500} << 20;  // bytes of a request's body
  std::string token;                                  // empty: a random one
};

class Server {
 public:
  explicit Server(ServerConfig config);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;
  // Binds the address; returns the port. Throws std::runtime_error when it cannot.
  int bind();
  // The model given on the command line (copied into the work folder), which the page opens first; the
  // scale it starts with. Throws poreshell::Error for a model the readers refuse.
  void open_model(const std::filesystem::path& path, const std::string& units);
  void set_scale(double scale);
  // Serves until stop(); returns false when serving failed.
  bool run();
  // Cancels the preview and the job running (its files removed), then stops serving. Thread-safe; not
  // async-signal-safe (call it from a thread, e.g. one waiting in sigwait).
  void stop();
  const std::string& token() const;
  int port() const;

  struct Impl;  // the routes' state (server_impl.hpp)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace studio
