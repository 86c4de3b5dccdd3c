// One of three equal servers for bench/studio/http_libraries: GET /health a short JSON, GET /big 4 MB.
#include <httplib.h>

#include <cstdio>
#include <string>

int main() {
  httplib::Server server;
  server.set_tcp_nodelay(true);  // as the studio: no 40 ms delayed-ACK stall between header and body
  const std::string big(4 << 20, 'x');
  server.Get("/health", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("{\"version\":\"0\"}", "application/json; charset=utf-8");
  });
  server.Get("/big", [&](const httplib::Request&, httplib::Response& res) {
    res.set_content(big, "application/octet-stream");
  });
  const int port = server.bind_to_any_port("127.0.0.1");
  std::printf("%d\n", port);
  std::fflush(stdout);
  server.listen_after_bind();
}
