#include "server/connections.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

namespace brdfbake::server {

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t')) --b;
  return s.substr(a, b - a);
}

const char* reason(int status) {
  switch (status) {
    case 400:
      return "Bad Request";
    case 408:
      return "Request Timeout";
    case 413:
      return "Payload Too Large";
    case 415:
      return "Unsupported Media Type";
    case 417:
      return "Expectation Failed";
    case 431:
      return "Request Header Fields Too Large";
    case 501:
      return "Not Implemented";
    default:
      return "Service Unavailable";
  }
}

// A reply of this layer: {"error": message}, and the connection closes after it.
std::string canned(int status, const std::string& message, int retry_after = 0) {
  nlohmann::json o;
  o["error"] = message;
  const std::string body = o.dump(2) + "\n";
  std::string r = "HTTP/1.1 " + std::to_string(status) + " " + reason(status) +
                  "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
                  "\r\nConnection: close\r\n";
  if (retry_after > 0) r += "Retry-After: " + std::to_string(retry_after) + "\r\n";
  return r + "\r\n" + body;
}

// "127.0.0.1" and the port of a socket address.
void address_text(const sockaddr_storage& a, std::string& ip, int& port) {
  char buf[INET6_ADDRSTRLEN] = {};
  if (a.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
    ::inet_ntop(AF_INET, &v4->sin_addr, buf, sizeof buf);
    port = ntohs(v4->sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
    ::inet_ntop(AF_INET6, &v6->sin6_addr, buf, sizeof buf);
    port = ntohs(v6->sin6_port);
  } else {
    port = 0;
  }
  ip = buf;
}

// The requests that never wait and never take long: whatever else the server does, a reserve of
// workers answers them.
bool light_request(const std::string& method, const std::string& target) {
  if (method != "GET") return false;
  const size_t q = target.find('?');
  const std::string path = target.substr(0, q);
  if (path == "/v1/health" || path == "/v1/devices" || path == "/metrics") return true;
  const std::string jobs = "/v1/jobs/";
  if (path.size() <= jobs.size() || path.compare(0, jobs.size(), jobs) != 0) return false;
  if (path.find('/', jobs.size()) != std::string::npos) return false;  // a file download
  if (q == std::string::npos) return true;
  // One job's status without a long poll (?wait=S).
  const std::string query = target.substr(q + 1);
  for (size_t at = 0; at <= query.size();) {
    const size_t amp = std::min(query.find('&', at), query.size());
    const std::string part = query.substr(at, amp - at);
    if (part.substr(0, part.find('=')) == "wait") return false;
    at = amp + 1;
  }
  return true;
}

}  // namespace

// One client connection, owned by the reader while it waits for a request, by a worker while
// that request is handled.
struct Connection {
  int fd = -1;
  std::string ip, local_ip;
  int port = 0, local_port = 0;
  std::string over_cap;  // why it is beyond a cap ("" when within): only light requests are served

  enum class Phase { Waiting, Head, Body, Chunked, Closing } phase = Phase::Waiting;
  double deadline = 0;  // of the request being received (or of the idle wait, or of the closing)
  std::string in;       // bytes received and not yet consumed by a request
  size_t scan = 0;      // where the search for the end of the head resumes
  size_t pos = 0;       // the next byte of `in` the body parser reads
  std::string head;     // request line and headers as cpp-httplib will read them
  std::string body;
  size_t length = 0;  // Content-Length
  enum class Chunk { Size, Data, DataEnd, Trailers } chunk = Chunk::Size;
  size_t chunk_left = 0;
  bool light = false;
  int served = 0;
  std::uint64_t reserved = 0;  // bytes counted in the buffered budget
  std::size_t max_body = 0;    // this request's limit: --max-body, or --max-upload for POST /v1/uploads
  bool upload = false;
  std::string out;  // a reply of this layer still being sent (Closing)
};

class GuardedServer::Engine {
 public:
  Engine(GuardedServer& owner, ConnectionLimits limits) : owner_(owner), limits_(limits) {}

  void set_limits(const ConnectionLimits& l) {
    std::lock_guard<std::mutex> lock(mutex_);
    limits_ = l;
  }
  void set_on_refused(std::function<void(int)> f) {
    std::lock_guard<std::mutex> lock(mutex_);
    on_refused_ = std::move(f);
  }

  ConnectionCounts counts() const {
    std::lock_guard<std::mutex> lock(mutex_);
    ConnectionCounts c;
    c.open = open_;
    c.reading = reading_;
    c.queued = static_cast<int>(light_.size() + heavy_.size());
    c.working = working_;
    return c;
  }

  void start() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (running_) return;
    if (wake_[0] < 0 && ::pipe2(wake_, O_CLOEXEC | O_NONBLOCK) != 0) wake_[0] = wake_[1] = -1;
    running_ = true;
    stopping_ = false;
    reader_ = std::thread([this] { read_loop(); });
    const int general = std::max(1, limits_.workers), reserve = std::max(1, limits_.reserve);
    for (int i = 0; i < general + reserve; ++i)
      workers_.emplace_back([this, light_only = i >= general] { work_loop(light_only); });
  }

  // Stops reading requests; what workers hold is finished (its replies say Connection: close).
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!running_) return;
      stopping_ = true;
    }
    wake();
    general_cv_.notify_all();
    reserve_cv_.notify_all();
    if (reader_.joinable()) reader_.join();
    for (auto& w : workers_)
      if (w.joinable()) w.join();
    workers_.clear();
    std::lock_guard<std::mutex> lock(mutex_);
    for (Connection* c : returned_) close_now(c);
    returned_.clear();
    running_ = false;
  }

  ~Engine() {
    stop();
    if (wake_[0] >= 0) ::close(wake_[0]);
    if (wake_[1] >= 0) ::close(wake_[1]);
  }

  // cpp-httplib's accept loop hands over a new connection (on its thread; must not block).
  void accept(int fd) {
    sockaddr_storage peer{}, local{};
    socklen_t n = sizeof peer;
    auto* c = new Connection;
    c->fd = fd;
    if (::getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &n) == 0) address_text(peer, c->ip, c->port);
    n = sizeof local;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &n) == 0)
      address_text(local, c->local_ip, c->local_port);
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    int yes = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
    std::unique_lock<std::mutex> lock(mutex_);
    if (stopping_ || !running_) {
      lock.unlock();
      ::close(fd);
      delete c;
      return;
    }
    const auto known = per_client_.find(c->ip);
    const int from_client = known == per_client_.end() ? 0 : known->second;
    if (open_ >= limits_.max_connections + limits_.reserve_connections) {
      // Not even read: the reserve for light requests is taken too.
      const std::string reply = canned(503,
                                       "too many connections (" + std::to_string(open_) + " open, --max-connections " +
                                           std::to_string(limits_.max_connections) + "); retry later",
                                       1);
      auto refused = on_refused_;
      lock.unlock();
      (void)::send(fd, reply.data(), reply.size(), MSG_NOSIGNAL);
      ::close(fd);
      delete c;
      if (refused) refused(503);
      return;
    }
    if (open_ >= limits_.max_connections)
      c->over_cap = "too many connections (" + std::to_string(open_) + " open, --max-connections " +
                    std::to_string(limits_.max_connections) + "); retry later";
    else if (from_client >= limits_.max_client_connections)
      c->over_cap = "too many connections from " + c->ip + " (" + std::to_string(from_client) +
                    " open, --max-client-connections " + std::to_string(limits_.max_client_connections) +
                    "); retry later";
    ++open_;
    ++per_client_[c->ip];
    // Beyond a cap, a connection gets a short while to say what it wants.
    c->deadline = now() + (c->over_cap.empty() ? limits_.request_seconds : std::min(limits_.request_seconds, 2.0));
    returned_.push_back(c);
    lock.unlock();
    wake();
  }

 private:
  void wake() {
    if (wake_[1] >= 0) {
      const char b = 1;
      (void)!::write(wake_[1], &b, 1);
    }
  }

  // Closes and forgets a connection. mutex_ held.
  void close_now(Connection* c) {
    if (c->reserved) buffered_ -= c->reserved;
    ::close(c->fd);
    --open_;
    auto it = per_client_.find(c->ip);
    if (it != per_client_.end() && --it->second <= 0) per_client_.erase(it);
    delete c;
  }

  // Sends a reply of this layer, then lingers (reads and drops what the client still sends, for a
  // second at most) before closing, so that the reply is not lost to a reset. mutex_ held.
  void refuse(Connection* c, int status, const std::string& message, int retry_after = 0) {
    c->out = canned(status, message, retry_after);
    c->phase = Connection::Phase::Closing;
    c->deadline = now() + 1.0;
    if (c->reserved) {
      buffered_ -= c->reserved;
      c->reserved = 0;
    }
    if (on_refused_) refused_.push_back(status);
  }

  // After a reply that ends the connection: no more is sent, what comes is read and dropped.
  static void start_closing(Connection* c) {
    ::shutdown(c->fd, SHUT_WR);
    c->phase = Connection::Phase::Closing;
    c->deadline = now() + 1.0;
  }

  enum class Parse { More, Ready, Refused };

  // Advances the request in c->in. mutex_ held (the budget and the limits).
  Parse parse(Connection* c) {
    using P = Connection::Phase;
    if (c->phase == P::Waiting) {
      // Empty lines before a request line are skipped (RFC 9112, 2.2).
      size_t skip = 0;
      while (skip + 1 < c->in.size() && c->in[skip] == '\r' && c->in[skip + 1] == '\n') skip += 2;
      c->in.erase(0, skip);
      if (c->in.empty() || (c->in.size() == 1 && c->in[0] == '\r')) return Parse::More;
      c->phase = P::Head;
      c->scan = 0;
      c->deadline = now() + limits_.request_seconds;  // from the request's first byte
    }
    if (c->phase == P::Head) {
      const size_t end = c->in.find("\r\n\r\n", c->scan >= 3 ? c->scan - 3 : 0);
      if (end == std::string::npos || end + 4 > limits_.max_head) {
        if (c->in.size() > limits_.max_head || end != std::string::npos) {
          refuse(c, 431, "request line and headers larger than " + std::to_string(limits_.max_head) + " bytes");
          return Parse::Refused;
        }
        c->scan = c->in.size();
        return Parse::More;
      }
      if (!read_head(c, end)) return Parse::Refused;
    }
    if (c->phase == P::Body) {
      if (c->in.size() - c->pos < c->length) return Parse::More;
      c->body.assign(c->in, c->pos, c->length);
      c->pos += c->length;
      return finish(c);
    }
    if (c->phase == P::Chunked) return read_chunks(c);
    return finish(c);
  }

  // The head ends at `end` (its blank line): checks it and chooses how the body is framed.
  bool read_head(Connection* c, size_t end) {
    const std::string raw = c->in.substr(0, end + 2);
    c->pos = end + 4;
    std::vector<std::string> lines;
    for (size_t at = 0; at < raw.size();) {
      const size_t eol = raw.find("\r\n", at);
      lines.push_back(raw.substr(at, eol - at));
      at = eol + 2;
    }
    const std::string& request_line = lines.front();
    const size_t s1 = request_line.find(' '), s2 = request_line.rfind(' ');
    if (s1 == std::string::npos || s2 == s1 || request_line.compare(s2 + 1, 5, "HTTP/") != 0) {
      refuse(c, 400, "malformed HTTP request line");
      return false;
    }
    const std::string method = request_line.substr(0, s1), target = request_line.substr(s1 + 1, s2 - s1 - 1);
    std::string head = request_line + "\r\n";
    std::string te, expect, encoding;
    bool has_length = false, form = false;
    for (size_t i = 1; i < lines.size(); ++i) {
      const std::string& line = lines[i];
      const size_t colon = line.find(':');
      if (colon == std::string::npos || colon == 0 || line.find_first_of(" \t") < colon) {
        refuse(c, 400, "malformed HTTP header line");
        return false;
      }
      const std::string name = lower(line.substr(0, colon)), value = trim(line.substr(colon + 1));
      if (name == "content-length") {
        if (value.empty() || value.size() > 18 || value.find_first_not_of("0123456789") != std::string::npos) {
          refuse(c, 400, "Content-Length must be a number of bytes");
          return false;
        }
        const size_t n = static_cast<size_t>(std::stoull(value));
        if (has_length && n != c->length) {
          refuse(c, 400, "two different Content-Length headers");
          return false;
        }
        has_length = true;
        c->length = n;
        continue;
      }
      if (name == "transfer-encoding") {
        te = te.empty() ? lower(value) : te + "," + lower(value);
        continue;
      }
      if (name == "expect") {
        expect = lower(value);
        continue;
      }
      if (name == "content-encoding") encoding = lower(value);
      if (name == "content-type") {
        const std::string type = lower(value);
        if (type.rfind("multipart/", 0) == 0) {
          refuse(c, 415,
                 "a multipart form is not a request body this server reads: send the JSON document itself "
                 "(curl --data-binary @job.json, not -F)");
          return false;
        }
        // curl -d and --data-binary send this type by default: the body is the JSON it holds, not a form.
        if (type.rfind("application/x-www-form-urlencoded", 0) == 0) {
          form = true;
          continue;
        }
      }
      head += line + "\r\n";
    }
    if (!encoding.empty() && encoding != "identity") {
      refuse(c, 415, "Content-Encoding '" + encoding.substr(0, 40) + "' is not accepted: send the JSON body as it is");
      return false;
    }
    if (!te.empty() && te != "chunked") {
      refuse(c, 501, "Transfer-Encoding '" + te.substr(0, 40) + "' is not supported (chunked, or a Content-Length)");
      return false;
    }
    if (!te.empty() && has_length) {
      refuse(c, 400, "both Transfer-Encoding and Content-Length");
      return false;
    }
    c->upload = method == "POST" && target.substr(0, target.find('?')) == "/v1/uploads";
    c->max_body = c->upload ? limits_.max_upload : limits_.max_body;
    if (has_length && c->length > c->max_body) {
      refuse(c, 413, too_large(c, std::to_string(c->length) + " bytes"));
      return false;
    }
    if (form) head += "Content-Type: application/json\r\n";
    c->head = std::move(head);
    c->light = light_request(method, target);
    const bool chunked = !te.empty();
    if (!expect.empty()) {
      if (expect != "100-continue") {
        refuse(c, 417, "Expect '" + expect.substr(0, 40) + "' is not supported (only 100-continue)");
        return false;
      }
      if (chunked || c->length > 0) {
        static const char kContinue[] = "HTTP/1.1 100 Continue\r\n\r\n";
        (void)::send(c->fd, kContinue, sizeof kContinue - 1, MSG_NOSIGNAL);
      }
    }
    if (!reserve(c, chunked ? 0 : c->length)) return false;
    c->phase = chunked ? Connection::Phase::Chunked : Connection::Phase::Body;
    c->chunk = Connection::Chunk::Size;
    if (!chunked && !has_length) c->length = 0;
    return true;
  }

  // Counts `bytes` more of this request in the budget of bytes held at once.
  // The 413 line: the body's size, the limit and the option that raises it.
  static std::string too_large(const Connection* c, const std::string& size) {
    if (c->upload)
      return "upload of " + size + " is larger than the server takes (" + std::to_string(c->max_body) +
             " bytes): start it with a larger --max-upload (e.g. --max-upload 256M)";
    return "request body of " + size + " is larger than the server accepts (" + std::to_string(c->max_body) +
           " bytes, --max-body)";
  }

  bool reserve(Connection* c, std::uint64_t bytes) {
    if (buffered_ + bytes > limits_.max_buffered) {
      refuse(c, 503, "the server is receiving too many request bodies at once; retry later", 1);
      return false;
    }
    buffered_ += bytes;
    c->reserved += bytes;
    return true;
  }

  Parse read_chunks(Connection* c) {
    using K = Connection::Chunk;
    for (;;) {
      if (c->chunk == K::Size || c->chunk == K::Trailers) {
        const size_t eol = c->in.find("\r\n", c->pos);
        if (eol == std::string::npos) {
          if (c->in.size() - c->pos > 4096) {
            refuse(c, 400, "malformed chunked body");
            return Parse::Refused;
          }
          return Parse::More;
        }
        const std::string line = c->in.substr(c->pos, eol - c->pos);
        c->pos = eol + 2;
        if (c->chunk == K::Trailers) {
          if (line.empty()) return finish(c);
          continue;  // a trailer field: dropped
        }
        const std::string digits = line.substr(0, line.find_first_of("; \t"));
        if (digits.empty() || digits.size() > 15 ||
            digits.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) {
          refuse(c, 400, "malformed chunked body (chunk size)");
          return Parse::Refused;
        }
        c->chunk_left = static_cast<size_t>(std::stoull(digits, nullptr, 16));
        if (c->chunk_left == 0) {
          c->chunk = K::Trailers;
          continue;
        }
        if (c->body.size() + c->chunk_left > c->max_body) {
          refuse(c, 413, too_large(c, "more than that"));
          return Parse::Refused;
        }
        if (!reserve(c, c->chunk_left)) return Parse::Refused;
        c->chunk = K::Data;
      }
      if (c->chunk == K::Data) {
        const size_t take = std::min(c->chunk_left, c->in.size() - c->pos);
        c->body.append(c->in, c->pos, take);
        c->pos += take;
        c->chunk_left -= take;
        if (c->chunk_left > 0) return Parse::More;
        c->chunk = K::DataEnd;
      }
      if (c->chunk == K::DataEnd) {
        if (c->in.size() - c->pos < 2) return Parse::More;
        if (c->in.compare(c->pos, 2, "\r\n") != 0) {
          refuse(c, 400, "malformed chunked body (no CRLF after a chunk)");
          return Parse::Refused;
        }
        c->pos += 2;
        c->chunk = K::Size;
      }
    }
  }

  // The request is complete: its framing is a Content-Length now; what follows it stays in `in`.
  Parse finish(Connection* c) {
    c->head += "Content-Length: " + std::to_string(c->body.size()) + "\r\n\r\n";
    c->in.erase(0, c->pos);
    c->pos = 0;
    c->scan = 0;
    if (!c->over_cap.empty() && !c->light) {
      refuse(c, 503, c->over_cap, 1);
      return Parse::Refused;
    }
    return Parse::Ready;
  }

  void read_loop() {
    std::vector<Connection*> conns;
    std::vector<pollfd> fds;
    std::vector<int> refused;
    std::function<void(int)> on_refused;
    for (;;) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (Connection* c : returned_) conns.push_back(c);
        returned_.clear();
        if (stopping_) {
          for (Connection* c : conns) close_now(c);
          reading_ = 0;
          return;
        }
      }
      // Requests already complete in what was received (pipelined), and the deadlines.
      const double t = now();
      double next = t + 1.0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (size_t i = 0; i < conns.size();) {
          Connection* c = conns[i];
          bool keep = true;
          const Parse p = c->phase == Connection::Phase::Closing || c->in.empty() ? Parse::More : parse(c);
          if (p == Parse::Ready) {
            dispatch(c);
            keep = false;
          } else if (p == Parse::Refused) {
            send_pending(c);
            next = std::min(next, c->deadline);
          } else if (t >= c->deadline) {
            if (c->phase == Connection::Phase::Head || c->phase == Connection::Phase::Body ||
                c->phase == Connection::Phase::Chunked) {
              char m[160];
              std::snprintf(m, sizeof m,
                            "the request did not arrive within %g s (--io-timeout: headers and body together)",
                            limits_.request_seconds);
              refuse(c, 408, m);
              send_pending(c);
              next = std::min(next, c->deadline);
            } else {
              close_now(c);
              keep = false;
            }
          } else {
            next = std::min(next, c->deadline);
          }
          if (keep)
            ++i;
          else
            conns.erase(conns.begin() + static_cast<std::ptrdiff_t>(i));
        }
        reading_ = static_cast<int>(conns.size());
        refused.swap(refused_);
        on_refused = on_refused_;
      }
      for (int status : refused)
        if (on_refused) on_refused(status);
      refused.clear();

      fds.assign(1, pollfd{wake_[0], POLLIN, 0});
      for (Connection* c : conns)
        fds.push_back(pollfd{c->fd, static_cast<short>(POLLIN | (c->out.empty() ? 0 : POLLOUT)), 0});
      const int wait_ms = static_cast<int>(std::clamp((next - now()) * 1000.0 + 1.0, 0.0, 1000.0));
      const int ready = ::poll(fds.data(), fds.size(), wait_ms);
      if (ready < 0 && errno != EINTR) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      if (ready <= 0) continue;
      if (fds[0].revents) {
        char drain[256];
        while (::read(wake_[0], drain, sizeof drain) > 0) {
        }
      }
      std::lock_guard<std::mutex> lock(mutex_);
      std::vector<Connection*> keep;
      keep.reserve(conns.size());
      for (size_t i = 0; i < conns.size(); ++i) {
        Connection* c = conns[i];
        const short ev = fds[i + 1].revents;
        if (ev == 0) {
          keep.push_back(c);
          continue;
        }
        if (!c->out.empty() && (ev & POLLOUT)) send_pending(c);
        if (!receive(c)) {
          close_now(c);
          continue;
        }
        if (c->phase == Connection::Phase::Closing) {
          keep.push_back(c);
          continue;
        }
        const Parse p = c->in.empty() ? Parse::More : parse(c);
        if (p == Parse::Ready) {
          dispatch(c);
          continue;
        }
        if (p == Parse::Refused) send_pending(c);
        keep.push_back(c);
      }
      conns.swap(keep);
    }
  }

  // Reads what the socket has (a bounded amount); false when the connection is over (closed by
  // the client, an error, or a closing connection drained).
  bool receive(Connection* c) {
    char buf[1 << 16];
    for (int rounds = 0; rounds < 4; ++rounds) {
      const ssize_t n = ::recv(c->fd, buf, sizeof buf, 0);
      if (n > 0) {
        if (c->phase != Connection::Phase::Closing) c->in.append(buf, static_cast<size_t>(n));
        if (c->phase == Connection::Phase::Head && c->in.size() > limits_.max_head + 4) return true;
        continue;
      }
      if (n == 0) return false;  // the client closed its side
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return true;
      return false;
    }
    return true;
  }

  // Sends what remains of a reply of this layer; once it is all sent, the sending side closes.
  static void send_pending(Connection* c) {
    while (!c->out.empty()) {
      const ssize_t n = ::send(c->fd, c->out.data(), c->out.size(), MSG_NOSIGNAL);
      if (n > 0) {
        c->out.erase(0, static_cast<size_t>(n));
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
      c->out.clear();  // the client is gone
    }
    ::shutdown(c->fd, SHUT_WR);
  }

  // A complete request to the workers. mutex_ held.
  void dispatch(Connection* c) {
    (c->light ? light_ : heavy_).push_back(c);
    // Each kind of worker has its own condition: a wake-up for a heavy request must not be taken
    // (and lost) by a worker of the reserve, which would not take it.
    general_cv_.notify_one();
    if (c->light) reserve_cv_.notify_one();
  }

  void work_loop(bool light_only) {
    for (;;) {
      Connection* c = nullptr;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        (light_only ? reserve_cv_ : general_cv_).wait(lock, [&] {
          return stopping_ || !light_.empty() || (!light_only && !heavy_.empty());
        });
        if (!light_.empty()) {
          c = light_.front();
          light_.pop_front();
        } else if (!light_only && !heavy_.empty()) {
          c = heavy_.front();
          heavy_.pop_front();
        } else {
          return;  // stopping, nothing left
        }
        ++working_;
      }
      handle(c);
      std::lock_guard<std::mutex> lock(mutex_);
      --working_;
    }
  }

  class RequestStream;
  void handle(Connection* c);

  GuardedServer& owner_;
  ConnectionLimits limits_;
  mutable std::mutex mutex_;
  std::condition_variable general_cv_, reserve_cv_;
  std::function<void(int)> on_refused_;
  std::vector<int> refused_;  // statuses to report (outside the lock)
  bool running_ = false, stopping_ = false;
  int wake_[2] = {-1, -1};
  std::thread reader_;
  std::vector<std::thread> workers_;
  std::vector<Connection*> returned_;  // to the reader: new, kept alive, or closing
  std::deque<Connection*> light_, heavy_;
  int open_ = 0, reading_ = 0, working_ = 0;
  std::map<std::string, int> per_client_;
  std::uint64_t buffered_ = 0;
};

// A complete request, read by cpp-httplib from memory; its reply written to the socket with the
// reply's deadlines, in writes of up to 64 KiB.
class GuardedServer::Engine::RequestStream final : public httplib::Stream {
 public:
  RequestStream(const Connection& c, std::string request, const ConnectionLimits& l)
      : c_(c), request_(std::move(request)), stall_(l.write_stall_seconds), rate_(l.min_send_rate) {}

  bool is_readable() const override { return at_ < request_.size(); }
  bool is_writable() const override { return !failed_; }
  ssize_t read(char* ptr, size_t size) override {
    const size_t n = std::min(size, request_.size() - at_);
    std::memcpy(ptr, request_.data() + at_, n);
    at_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (failed_) return -1;
    out_.append(ptr, size);
    if (out_.size() >= (1u << 16) && !flush()) return -1;
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = c_.ip;
    port = c_.port;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = c_.local_ip;
    port = c_.local_port;
  }
  socket_t socket() const override { return c_.fd; }

  // Sends what is buffered. A reply may stall `stall_` seconds at a time, and must average
  // `rate_` bytes per second once it has had `stall_` seconds.
  bool flush() {
    if (failed_) return false;
    if (start_ == 0) start_ = now();
    size_t off = 0;
    while (off < out_.size()) {
      const ssize_t n = ::send(c_.fd, out_.data() + off, out_.size() - off, MSG_NOSIGNAL);
      if (n > 0) {
        off += static_cast<size_t>(n);
        sent_ += static_cast<std::uint64_t>(n);
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        const double t = now();
        const double pending = double(sent_ + (out_.size() - off));
        const double until = std::min(t + stall_, start_ + stall_ + pending / rate_);
        if (t >= until) break;
        pollfd p{c_.fd, POLLOUT, 0};
        if (::poll(&p, 1, static_cast<int>((until - t) * 1000.0) + 1) <= 0) break;
        continue;
      }
      break;
    }
    if (off < out_.size()) failed_ = true;
    out_.clear();
    return !failed_;
  }
  bool failed() const { return failed_; }

 private:
  const Connection& c_;
  std::string request_;
  size_t at_ = 0;
  std::string out_;
  double stall_, rate_;
  double start_ = 0;
  std::uint64_t sent_ = 0;
  bool failed_ = false;
};

void GuardedServer::Engine::handle(Connection* c) {
  ConnectionLimits limits;
  bool stopping;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    limits = limits_;
    stopping = stopping_;
  }
  RequestStream stream(*c, c->head + c->body, limits);
  c->head.clear();
  c->body.clear();
  const bool close = stopping || !c->over_cap.empty() || ++c->served >= limits.max_requests_per_connection;
  bool closed = false;
  bool ok = false;
  try {
    ok = owner_.serve_request(stream, close, closed);
  } catch (...) {
    ok = false;
  }
  ok = stream.flush() && ok;
  std::lock_guard<std::mutex> lock(mutex_);
  if (c->reserved) {
    buffered_ -= c->reserved;
    c->reserved = 0;
  }
  if (!running_ || stopping_ || !ok || close || closed) {
    if (!running_) {
      close_now(c);
      return;
    }
    start_closing(c);
  } else {
    c->phase = Connection::Phase::Waiting;
    c->deadline = now() + limits.idle_seconds;
  }
  c->length = 0;
  c->light = false;
  returned_.push_back(c);
  wake();
}

namespace {

// cpp-httplib's task queue for the accept loop: each accepted connection goes to the engine at once.
class HandOver final : public httplib::TaskQueue {
 public:
  explicit HandOver(std::shared_ptr<GuardedServer::Engine> engine, std::function<void()> start,
                    std::function<void()> stop)
      : engine_(std::move(engine)), stop_(std::move(stop)) {
    start();
  }
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override { stop_(); }

 private:
  std::shared_ptr<GuardedServer::Engine> engine_;
  std::function<void()> stop_;
};

}  // namespace

GuardedServer::GuardedServer(ConnectionLimits limits) : engine_(std::make_shared<Engine>(*this, limits)) {
  new_task_queue = [this] {
    return new HandOver(
        engine_, [e = engine_] { e->start(); }, [e = engine_] { e->stop(); });
  };
}

GuardedServer::~GuardedServer() { engine_->stop(); }

void GuardedServer::set_limits(const ConnectionLimits& limits) { engine_->set_limits(limits); }
void GuardedServer::set_on_refused(std::function<void(int)> f) { engine_->set_on_refused(std::move(f)); }
ConnectionCounts GuardedServer::counts() const { return engine_->counts(); }

bool GuardedServer::process_and_close_socket(socket_t sock) {
  engine_->accept(sock);
  return true;
}

bool GuardedServer::serve_request(httplib::Stream& stream, bool close_connection, bool& connection_closed) {
  return process_request(stream, close_connection, connection_closed, nullptr);
}

}  // namespace brdfbake::server
