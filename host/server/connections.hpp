// The server's connections (docs/SERVICE.md, "Slow and heavy clients"). cpp-httplib serves each
// connection on a pool thread that blocks while the client sends, with a timeout per read: a client
// sending a byte every few seconds holds a thread forever, and a few dozen such clients leave every
// other client, health checks included, unanswered. Here no worker waits on a client:
//
//  - one reader thread receives every request (request line, headers and body) on non-blocking
//    sockets, and must have all of it within `request_seconds` of its first byte (of the accept,
//    for a new connection), not per read; a kept-alive connection may wait `idle_seconds` for the
//    next request. Too late: 408 and the connection is closed.
//  - only a complete request goes to a worker, which runs cpp-httplib's routing on it from memory
//    and writes the reply; a reply must keep moving (`write_stall_seconds` per stall, and a whole
//    reply at `min_send_rate` bytes per second after the first stall's worth), else it is cut.
//  - `reserve` more workers take only light requests (health, devices, metrics, one job's status
//    without ?wait), so that long polls and tables waiting for a device never leave them unanswered.
//  - connections are capped overall and per client address; beyond a cap, a connection is read
//    and answered 503, except the light requests (a small reserve of connections beyond the overall
//    cap is kept for them).
//  - bodies are framed here: Content-Length (at most `max_body`, else 413 before anything is read),
//    chunked (decoded, at most `max_body`), Expect: 100-continue answered; request bodies the API
//    cannot read are refused with their reason (415: a Content-Encoding, a multipart form; 501 an
//    unknown Transfer-Encoding); a form content type (`curl --data-binary`'s default) is the JSON
//    body it holds. The bytes held at once, all connections together, stay within `max_buffered`.
#pragma once

#include <httplib.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace brdfbake::server {

struct ConnectionLimits {
  double request_seconds = 30;        // a whole request (head and body) must arrive within this
  double idle_seconds = 5;            // a kept-alive connection waits this long for its next request
  double write_stall_seconds = 30;    // a reply may not move for this long
  double min_send_rate = 65536;       // bytes per second a long reply must average
  std::size_t max_body = 1 << 20;     // bytes of a request body (413 beyond)
  std::size_t max_upload = 64 << 20;  // bytes of a POST /v1/uploads body (413 beyond): a map of tens of MB
  std::size_t max_head = 64 << 10;    // bytes of a request line and headers (431 beyond)
  int workers = 64;                   // requests handled at once
  int reserve = 2;                    // more workers, for light requests only
  int max_connections = 512;          // connections open at once, all clients together
  int max_client_connections = 128;   // connections open at once from one address
  int reserve_connections = 32;       // beyond max_connections, for light requests only
  int max_requests_per_connection = 1000;
  std::uint64_t max_buffered = 256ull << 20;  // request bytes held at once, all connections
};

// Counts for tests and metrics.
struct ConnectionCounts {
  int open = 0;     // connections open
  int reading = 0;  // waiting for (the rest of) a request
  int queued = 0;   // complete requests waiting for a worker
  int working = 0;  // requests a worker handles
};

// cpp-httplib's Server with the connection handling above; routes, handlers and the rest of its
// API are cpp-httplib's. `on_refused(status)` is told of every reply sent by this layer itself
// (408, 413, 503, ...), which cpp-httplib's logger does not see.
class GuardedServer : public httplib::Server {
 public:
  explicit GuardedServer(ConnectionLimits limits = {});
  ~GuardedServer() override;
  GuardedServer(const GuardedServer&) = delete;
  GuardedServer& operator=(const GuardedServer&) = delete;

  void set_limits(const ConnectionLimits& limits);
  void set_on_refused(std::function<void(int status)> f);
  ConnectionCounts counts() const;

  class Engine;

 private:
  // Called by cpp-httplib's accept loop (through the task queue, inline) for each connection.
  bool process_and_close_socket(socket_t sock) override;
  // A complete request, on a worker: cpp-httplib's routing and reply (process_request).
  friend class Engine;
  bool serve_request(httplib::Stream& stream, bool close_connection, bool& connection_closed);

  std::shared_ptr<Engine> engine_;
};

}  // namespace brdfbake::server
