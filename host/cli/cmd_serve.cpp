// brdfbake serve [--listen 127.0.0.1:8737] --data DIR [--input-root DIR] [--token-file F]
//                [--devices SEL,...] [--max-queue N] [--max-body BYTES] [...]
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <thread>

#include "cli_common.hpp"
#include "server/server.hpp"
#include "server/site_policy.hpp"

namespace brdfbake::cli {

namespace {

// "1048576", "64K", "512M", "2G" (powers of 1024).
std::uint64_t byte_count(const cxxopts::ParseResult& r, const std::string& name) {
  const std::string text = r[name].as<std::string>();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  double scale = 1;
  const std::string unit = end ? std::string(end) : std::string();
  if (unit == "K" || unit == "k")
    scale = 1024.0;
  else if (unit == "M" || unit == "m")
    scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "g")
    scale = 1024.0 * 1024 * 1024;
  else if (!unit.empty())
    scale = -1;
  if (text.empty() || scale < 0 || !(v >= 0) || v * scale > 1e15)
    throw UsageError("--" + name + " must be a byte count such as 1048576, 64K, 512M or 2G (got '" + text + "')");
  return static_cast<std::uint64_t>(v * scale);
}

double seconds_option(const cxxopts::ParseResult& r, const std::string& name) {
  const double v = finite_number(r, name);
  if (v <= 0) throw UsageError("--" + name + " must be a positive number of seconds");
  return v;
}

}  // namespace

int cmd_serve(int argc, char** argv) {
  cxxopts::Options options("brdfbake serve", "Serve the job API over HTTP/1.1 (docs/SERVICE.md)");
  options.add_options()("listen",
                        "HOST:PORT to listen on; port 0 picks a free one (a non-loopback host needs --token-file)",
                        cxxopts::value<std::string>()->default_value("127.0.0.1:8737"))(
      "data", "the data directory: jobs.db (SQLite), jobs/<id>/ (outputs)", cxxopts::value<std::string>())(
      "input-root",
      "the only folder requests may read files from (environments, scenes, materials); none: builtin environments only",
      cxxopts::value<std::string>()->default_value(""))(
      "token-file", "a file whose first line is the bearer token every request must send",
      cxxopts::value<std::string>()->default_value(""))(
      "allowed-hosts",
      "comma-separated Host names answered beside loopback's and --listen's ('*': any); without a token others get 403",
      cxxopts::value<std::string>()->default_value(""))(
      "allowed-origins",
      "comma-separated origins (http://host:port) whose pages may POST or DELETE ('*': any); others get 403",
      cxxopts::value<std::string>()->default_value(""))(
      "devices", "comma-separated device selectors to serve (default: the default device); reference is always served",
      cxxopts::value<std::string>())("max-queue", "jobs waiting before submissions get 503 with Retry-After",
                                     cxxopts::value<std::string>()->default_value("64"))(
      "max-body", "largest request body (bytes, or 64K, 1M); larger gets 413",
      cxxopts::value<std::string>()->default_value("1M"))(
      "max-upload", "largest upload (POST /v1/uploads: an environment or scene file); larger gets 413",
      cxxopts::value<std::string>()->default_value("64M"))(
      "max-memory", "most memory one bake may need (bytes, or 512M, 2G); default: half the machine's",
      cxxopts::value<std::string>())("job-timeout", "seconds a job may run (a request's ?timeout= may ask for less)",
                                     cxxopts::value<std::string>()->default_value("3600"))(
      "table-timeout", "seconds POST /v1/tables waits for its table before 504",
      cxxopts::value<std::string>()->default_value("30"))(
      "io-timeout", "seconds a whole request (headers and body) may take to arrive, and a reply may stall",
      cxxopts::value<std::string>()->default_value("30"))("table-max",
                                                          "largest table POST /v1/tables bakes (estimated bytes)",
                                                          cxxopts::value<std::string>()->default_value("64M"))(
      "table-cache", "bytes of POST /v1/tables results kept for identical requests; 0: none",
      cxxopts::value<std::string>()->default_value("64M"))(
      "threads", "requests handled at once (a client still sending holds none; two more answer only health and status)",
      cxxopts::value<std::string>()->default_value("64"))(
      "max-connections", "connections open at once, all clients together (beyond: 503, but health and status)",
      cxxopts::value<std::string>()->default_value("512"))(
      "max-client-connections", "connections open at once from one address (beyond: 503, but health and status)",
      cxxopts::value<std::string>()->default_value("128"))(
      "shutdown-grace", "seconds running jobs get to finish on SIGTERM before they are stopped and re-queued",
      cxxopts::value<std::string>()->default_value("10"))(
      "url-file", "write the URL here once listening (for scripts, with port 0)",
      cxxopts::value<std::string>()->default_value(""))("no-warm-up", "do not build the common programs at start")(
      "h,help", "this help");
  const auto r = parse(options, argc, argv);
  if (r.count("help")) {
    std::cout << options.help() << "\nexample:\n  brdfbake serve --data /var/lib/brdfbake --input-root /srv/hdri\n";
    return 0;
  }
  if (!r.unmatched().empty()) throw UsageError("unexpected argument '" + r.unmatched().front() + "'");
  if (!r.count("data")) throw UsageError("--data DIR is required (where jobs and their files are kept)");

  server::ServerOptions o;
  const std::string listen = r["listen"].as<std::string>();
  const auto colon = listen.rfind(':');
  if (colon == std::string::npos || colon + 1 == listen.size())
    throw UsageError("--listen must be HOST:PORT (got '" + listen + "')");
  o.host = listen.substr(0, colon);
  if (o.host.size() > 2 && o.host.front() == '[' && o.host.back() == ']') o.host = o.host.substr(1, o.host.size() - 2);
  if (o.host.empty()) throw UsageError("--listen must name a host, e.g. 127.0.0.1:8737");
  const std::string port = listen.substr(colon + 1);
  char* end = nullptr;
  const long p = std::strtol(port.c_str(), &end, 10);
  if (*end != '\0' || p < 0 || p > 65535) throw UsageError("--listen: port must be 0..65535 (got '" + port + "')");
  o.port = static_cast<int>(p);
  o.data_dir = r["data"].as<std::string>();
  o.input_root = r["input-root"].as<std::string>();
  o.token_file = r["token-file"].as<std::string>();
  o.allowed_hosts = server::split_list(r["allowed-hosts"].as<std::string>());
  o.allowed_origins = server::split_list(r["allowed-origins"].as<std::string>());
  for (const auto& origin : o.allowed_origins)
    if (origin != "*" && origin.rfind("http://", 0) != 0 && origin.rfind("https://", 0) != 0)
      throw UsageError("--allowed-origins: '" + origin + "' is not an origin such as http://localhost:3000");
  const std::string devices = r.count("devices") ? r["devices"].as<std::string>() : std::string();
  for (size_t start = 0; !devices.empty();) {
    const size_t comma = devices.find(',', start);
    o.devices.push_back(devices.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  o.max_queue = integer(r, "max-queue");
  o.max_body = static_cast<std::size_t>(byte_count(r, "max-body"));
  o.max_upload = static_cast<std::size_t>(byte_count(r, "max-upload"));
  o.max_memory = r.count("max-memory") ? byte_count(r, "max-memory") : 0;  // 0: half the machine's
  o.job_timeout = seconds_option(r, "job-timeout");
  o.table_timeout = seconds_option(r, "table-timeout");
  o.io_timeout = seconds_option(r, "io-timeout");
  o.table_max_bytes = byte_count(r, "table-max");
  o.table_cache_bytes = byte_count(r, "table-cache");
  o.threads = integer(r, "threads");
  o.max_connections = integer(r, "max-connections");
  o.max_client_connections = integer(r, "max-client-connections");
  o.shutdown_grace = seconds_option(r, "shutdown-grace");
  o.url_file = r["url-file"].as<std::string>();
  o.warm_up = r.count("no-warm-up") == 0;
  if (o.max_queue < 1) throw UsageError("--max-queue must be at least 1");
  if (o.threads < 2 || o.threads > 1024) throw UsageError("--threads must be in 2..1024");
  if (o.max_connections < 1 || o.max_connections > 1000000) throw UsageError("--max-connections must be in 1..1000000");
  if (o.max_client_connections < 1 || o.max_client_connections > 1000000)
    throw UsageError("--max-client-connections must be in 1..1000000");
  if (o.max_body < 1024) throw UsageError("--max-body must be at least 1K");
  if (o.max_upload < 1024) throw UsageError("--max-upload must be at least 1K");

  // SIGTERM and SIGINT are taken by one thread (sigwait), so that shutdown runs outside a signal
  // handler; a client that hangs up must not kill the server (SIGPIPE).
  ::signal(SIGPIPE, SIG_IGN);
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);

  server::Server srv(o);
  std::printf("brdfbake serve: listening on %s (data %s%s%s)\n", srv.url().c_str(), o.data_dir.c_str(),
              o.input_root.empty() ? "; no input root: builtin environments only" : "; input root ",
              o.input_root.c_str());
  for (const auto& n : srv.recovery_notes()) std::printf("brdfbake serve: %s\n", n.c_str());
  std::fflush(stdout);

  std::thread signals([&] {
    int sig = 0;
    sigwait(&set, &sig);
    std::fprintf(stderr, "brdfbake serve: %s: stopping (running jobs get %g s)\n",
                 sig == SIGTERM ? "SIGTERM" : "SIGINT", o.shutdown_grace);
    if (!srv.stop()) {
      std::fprintf(stderr,
                   "brdfbake serve: a job is still inside a bake; leaving it to be re-queued at the next start\n");
      std::_Exit(0);
    }
  });
  const bool ok = srv.run();
  if (!ok) {
    std::fprintf(stderr, "brdfbake serve: listening on %s failed\n", srv.url().c_str());
    std::_Exit(kExitFailure);
  }
  signals.join();
  std::fprintf(stderr, "brdfbake serve: stopped\n");
  return 0;
}

}  // namespace brdfbake::cli
