// One of three equal servers for bench/studio/http_libraries: GET /health a short JSON, GET /big 4 MB.
// Boost.Beast, synchronous, a thread per connection (as cpp-httplib's pool and libmicrohttpd's mode).
#include <utility>  // before asio: Boost 1.74 uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/beast.hpp>

#include <cstdio>
#include <string>
#include <thread>

namespace beast = boost::beast;
namespace http = beast::http;
using tcp = boost::asio::ip::tcp;

static const std::string big(4 << 20, 'x');

static void session(tcp::socket socket) {
  beast::flat_buffer buffer;
  beast::error_code ec;
  for (;;) {
    http::request<http::string_body> req;
    http::read(socket, buffer, req, ec);
    if (ec) break;
    http::response<http::string_body> res{http::status::ok, req.version()};
    const bool is_big = req.target() == "/big";
    res.set(http::field::content_type, is_big ? "application/octet-stream" : "application/json");
    res.body() = is_big ? big : std::string("{\"version\":\"0\"}");
    res.keep_alive(req.keep_alive());
    res.prepare_payload();
    http::write(socket, res, ec);
    if (ec || !req.keep_alive()) break;
  }
  socket.shutdown(tcp::socket::shutdown_send, ec);
}

int main() {
  boost::asio::io_context io;
  tcp::acceptor acceptor{io, {boost::asio::ip::make_address("127.0.0.1"), 0}};
  std::printf("%u\n", acceptor.local_endpoint().port());
  std::fflush(stdout);
  for (;;) std::thread(session, acceptor.accept()).detach();
}
