// The HTTP library comparison (docs/BENCHMARKS.md, "Choosing the HTTP library"): libmicrohttpd
// serving the same two routes as httplib_server.cpp, with its internal epoll thread pool.
#include <microhttpd.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

std::string g_table(128 * 128 * 3 * 4, 'x');
const char kHealth[] = "{\"status\":\"ok\"}";

MHD_Result answer(void*, MHD_Connection* c, const char* url, const char*, const char*, const char*, size_t*, void**) {
  MHD_Response* r = nullptr;
  if (std::strcmp(url, "/table") == 0)
    r = MHD_create_response_from_buffer(g_table.size(), g_table.data(), MHD_RESPMEM_PERSISTENT);
  else
    r = MHD_create_response_from_buffer(sizeof kHealth - 1, const_cast<char*>(kHealth), MHD_RESPMEM_PERSISTENT);
  MHD_add_response_header(r, "Content-Type", "application/octet-stream");
  const MHD_Result ok = MHD_queue_response(c, MHD_HTTP_OK, r);
  MHD_destroy_response(r);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  const int port = argc > 1 ? std::atoi(argv[1]) : 18081;
  MHD_Daemon* d = MHD_start_daemon(MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_EPOLL, static_cast<uint16_t>(port),
                                   nullptr, nullptr, &answer, nullptr, MHD_OPTION_THREAD_POOL_SIZE, 2u,
                                   MHD_OPTION_CONNECTION_LIMIT, 256u, MHD_OPTION_END);
  if (!d) return 1;
  std::printf("libmicrohttpd %s on :%d\n", MHD_get_version(), port);
  std::fflush(stdout);
  pause();
  MHD_stop_daemon(d);
  return 0;
}
