// One of three equal servers for bench/studio/http_libraries: GET /health a short JSON, GET /big 4 MB.
#include <microhttpd.h>

#include <unistd.h>
#include <cstdio>
#include <cstring>
#include <string>

static std::string big(4 << 20, 'x');

static MHD_Result answer(void*, MHD_Connection* connection, const char* url, const char*, const char*,
                         const char*, size_t*, void**) {
  static const char health[] = "{\"version\":\"0\"}";
  const bool is_big = std::strcmp(url, "/big") == 0;
  MHD_Response* response =
      is_big ? MHD_create_response_from_buffer(big.size(), big.data(), MHD_RESPMEM_PERSISTENT)
             : MHD_create_response_from_buffer(sizeof health - 1, const_cast<char*>(health),
                                               MHD_RESPMEM_PERSISTENT);
  MHD_add_response_header(response, "Content-Type", is_big ? "application/octet-stream" : "application/json");
  const MHD_Result r = MHD_queue_response(connection, MHD_HTTP_OK, response);
  MHD_destroy_response(response);
  return r;
}

int main() {
  MHD_Daemon* daemon = MHD_start_daemon(MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_THREAD_PER_CONNECTION, 0,
                                        nullptr, nullptr, &answer, nullptr, MHD_OPTION_END);
  const MHD_DaemonInfo* info = MHD_get_daemon_info(daemon, MHD_DAEMON_INFO_BIND_PORT);
  std::printf("%u\n", info->port);
  std::fflush(stdout);
  pause();
}
