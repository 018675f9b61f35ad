// The HTTP library comparison (docs/BENCHMARKS.md, "Choosing the HTTP library"): cpp-httplib serving
// GET /health (a small JSON body) and GET /table (a 196,608-byte body, a 128x128 RGB float table).
#include <httplib.h>

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  const int port = argc > 1 ? std::atoi(argv[1]) : 18080;
  const std::string table(128 * 128 * 3 * 4, 'x');
  httplib::Server server;
  server.set_tcp_nodelay(true);
  server.set_keep_alive_max_count(1000);
  server.new_task_queue = [] { return new httplib::ThreadPool(64); };
  server.Get("/health", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("{\"status\":\"ok\"}", "application/json");
  });
  server.Get("/table", [&](const httplib::Request&, httplib::Response& res) {
    res.set_content(table, "application/octet-stream");
  });
  std::printf("cpp-httplib %s on 127.0.0.1:%d\n", CPPHTTPLIB_VERSION, port);
  std::fflush(stdout);
  return server.listen("127.0.0.1", port) ? 0 : 1;
}
