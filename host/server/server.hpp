// `brdfbake serve`: an HTTP/1.1 JSON server over the job API (docs/SERVICE.md). Jobs are the
// `brdfbake run` documents; they are stored in SQLite under the data directory, queued per device,
// run on warm devices and written under DATA/jobs/<id>/ all or nothing, so that a file is served
// only once its job is done. Every input path a request names is confined to the input root.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace brdfbake::server {

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8737;                                // 0: any free port (see url())
  std::string data_dir;                           // required: jobs.db, jobs/<id>/, tmp/
  std::string input_root;                         // "" = requests may read no file (builtin environments only)
  std::string token_file;                         // "" = no token (then only a loopback address is accepted)
  std::vector<std::string> allowed_hosts;         // Host names answered beside loopback and the listen host; "*" any
  std::vector<std::string> allowed_origins;       // origins whose pages may write (POST, DELETE); "*" any
  std::vector<std::string> devices;               // selectors to serve ("" = the default device); reference always
  int max_queue = 64;                             // waiting jobs before 503
  std::size_t max_body = 1 << 20;                 // bytes of a request body before 413
  std::size_t max_upload = 64 << 20;              // bytes of an upload (POST /v1/uploads) before 413
  double job_timeout = 3600;                      // seconds a job may run (a request may ask for less)
  double table_timeout = 30;                      // seconds POST /v1/tables waits for its table before 504
  double io_timeout = 30;                         // seconds a whole request (headers and body) may take to arrive,
                                                  // and a reply may stall
  std::uint64_t max_memory = 0;                   // bytes a bake may need; 0 = half the machine's memory
  std::uint64_t table_max_bytes = 64ull << 20;    // POST /v1/tables: the largest table (estimate)
  std::uint64_t table_cache_bytes = 64ull << 20;  // POST /v1/tables: results kept; 0 = no cache
  int threads = 64;                               // requests handled at once (a client sending slowly holds none)
  int max_connections = 512;                      // connections open at once, all clients together
  int max_client_connections = 128;               // connections open at once from one address
  double shutdown_grace = 10;                     // seconds running jobs get to finish on SIGTERM
  std::string url_file;                           // written with the URL once listening
  bool warm_up = true;                            // build the common programs at start
};

// The address is a loopback one (127.0.0.0/8, ::1, localhost).
bool is_loopback(const std::string& host);

class Server {
 public:
  // Checks the options (a non-loopback address needs a token file), takes the data directory's
  // lock, opens the job store, recovers what a crash left, opens the devices and binds the port.
  // Throws Error with a one-line message.
  explicit Server(ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // "http://127.0.0.1:8737", the port the server really listens on.
  std::string url() const;
  // What recovery did at start, one line each (for the start-up message).
  const std::vector<std::string>& recovery_notes() const;
  // Serves until stop() is called; false when listening failed.
  bool run();
  // Thread-safe: stops listening and the devices (jobs get shutdown_grace seconds, then are stopped
  // and re-queued). True when every device worker stopped.
  bool stop();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace brdfbake::server
