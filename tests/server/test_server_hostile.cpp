// brdfbake serve against slow, heavy and odd clients (issue 24, "The server under a slow or heavy
// client"): clients trickling their requests, long polls filling the workers, connection floods,
// bodies framed and typed as curl, Python and cpp-httplib send them, a table request abandoned
// past its timeout, a running job cancelled just before the server is killed. Each test asserts
// what is answered and what is not, never a wall time; every wait is bounded, every server
// listens on 127.0.0.1.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <atomic>
#include <thread>

#include "server/server_process.hpp"

namespace brdfbake::test {
namespace {

// A raw client connection, for what httplib::Client will not send.
class RawSocket {
 public:
  explicit RawSocket(int port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~RawSocket() {
    if (fd_ >= 0) ::close(fd_);
  }
  RawSocket(const RawSocket&) = delete;
  RawSocket& operator=(const RawSocket&) = delete;
  bool connected() const { return connected_; }
  bool send(const std::string& s) {
    return ::send(fd_, s.data(), s.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(s.size());
  }
  // What arrives within `seconds` (until the server closes, or `until` is in it).
  std::string receive(double seconds, const std::string& until = {}) {
    std::string got;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
      const double left = std::chrono::duration<double>(end - std::chrono::steady_clock::now()).count();
      if (left <= 0) break;
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left * 1000) + 1) <= 0) break;
      char buf[4096];
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) break;
      got.append(buf, static_cast<size_t>(n));
      if (!until.empty() && got.find(until) != std::string::npos) break;
    }
    return got;
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
};

// The status code of a raw reply ("HTTP/1.1 413 ..." -> 413), 0 when there is none.
int status_of(const std::string& reply) {
  if (reply.rfind("HTTP/1.1 ", 0) != 0 || reply.size() < 12) return 0;
  return std::atoi(reply.substr(9, 3).c_str());
}

// A fresh client that gives up after `seconds`: "answered" means answered within it.
httplib::Client impatient(const ServerProcess& s, double seconds = 2.0) {
  httplib::Client c(s.url());
  c.set_connection_timeout(std::chrono::duration<double>(seconds));
  c.set_read_timeout(std::chrono::duration<double>(seconds));
  c.set_write_timeout(std::chrono::duration<double>(seconds));
  return c;
}

// A job of `bytes` bytes or more: many small Schlick tables.
json job_of_bytes(size_t bytes) {
  json j = json::parse(R"({"brdfbake_job": 1, "tables": []})");
  for (int i = 0; j.dump().size() < bytes; ++i)
    j["tables"].push_back({{"kind", "fresnel"},
                           {"model", "schlick"},
                           {"f0", 0.04},
                           {"size", 4},
                           {"output", "f" + std::to_string(i) + ".csv"}});
  return j;
}

// A job that keeps the reference device busy for minutes (a 1024² DFG table of converged
// integrals, about 0.1 s a row on two cores), stopped at its next row when cancelled.
json reference_job() {
  return json::parse(R"({"device": "reference", "tables": [{"kind": "ggx", "size": 1024, "output": "slow.exr"},
                                                            {"kind": "ggx", "size": 4, "output": "after.exr"}]})");
}

bool wait_state(httplib::Client& c, const std::string& id, const std::string& state, double seconds = 30) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < until) {
    auto r = c.Get(("/v1/jobs/" + id).c_str());
    if (r && body_json(r).value("state", "") == state) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// 70 connections sending a request one byte every 0.4 s: the server keeps answering everyone
// else meanwhile, and answers each trickler 408 once --io-timeout has passed since its first byte
// (a deadline for the whole request, not for each read).
TEST(ServerHostile, TricklingClientsDoNotStarveOthers) {
  TempDir dir("trickle");
  ServerProcess server(dir.path,
                       {"--data", (dir.path / "data").string(), "--io-timeout", "3", "--threads", "4", "--no-warm-up"});
  ASSERT_TRUE(server.start()) << server.error();
  const std::string head =
      "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n";
  std::vector<std::unique_ptr<RawSocket>> tricklers;
  for (int i = 0; i < 70; ++i) {
    tricklers.push_back(std::make_unique<RawSocket>(server.port()));
    ASSERT_TRUE(tricklers.back()->connected());
  }
  int health_answered = 0, jobs_accepted = 0, rounds = 0;
  // 2.4 s of trickling (6 bytes each): within the 3 s the first byte allows.
  for (size_t at = 0; at < 6; ++at, ++rounds) {
    for (auto& t : tricklers) t->send(head.substr(at, 1));
    auto c = impatient(server);
    auto h = c.Get("/v1/health");
    health_answered += h && h->status == 200;
    auto j = c.Post("/v1/jobs", json::parse(R"({"tables": [{"kind": "ggx", "size": 4}]})").dump(), "application/json");
    jobs_accepted += j && j->status == 202;
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
  }
  EXPECT_EQ(health_answered, rounds) << "health went unanswered while slow clients sent their requests";
  EXPECT_EQ(jobs_accepted, rounds) << "other clients went unanswered while slow clients sent their requests";
  // Each trickler is answered 408 (its request never completed), at most --io-timeout after its
  // first byte; bounded here at 10 s for all of them.
  int timed_out = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (auto& t : tricklers) {
    const double left = std::max(0.0, std::chrono::duration<double>(until - std::chrono::steady_clock::now()).count());
    const std::string reply = t->receive(left, "\r\n\r\n");
    timed_out += status_of(reply) == 408;
  }
  EXPECT_EQ(timed_out, 70);
  auto c = impatient(server);
  auto m = c.Get("/metrics");
  ASSERT_TRUE(m);
  EXPECT_NE(m->body.find("brdfbake_http_requests_total{code=\"408\"} 70"), std::string::npos) << m->body;
}

// Every worker taken by a long poll: health, devices and a job's status are still answered (a
// reserve of workers takes only those).
TEST(ServerHostile, LongPollsLeaveHealthAndStatusAnswered) {
  TempDir dir("longpoll");
  ServerProcess server(dir.path, {"--data", (dir.path / "data").string(), "--threads", "2", "--no-warm-up"});
  ASSERT_TRUE(server.start()) << server.error();
  auto c = server.client();
  const std::string id = submit(c, reference_job());
  ASSERT_FALSE(id.empty());
  ASSERT_TRUE(wait_state(c, id, "running"));
  std::atomic<int> polls_done{0};
  std::vector<std::thread> polls;
  struct JoinAll {
    std::vector<std::thread>& threads;
    ~JoinAll() {
      for (auto& t : threads)
        if (t.joinable()) t.join();
    }
  } join_all{polls};
  for (int i = 0; i < 4; ++i)
    polls.emplace_back([&] {
      httplib::Client p(server.url());
      p.set_read_timeout(30, 0);
      (void)p.Get(("/v1/jobs/" + id + "?wait=5").c_str());
      ++polls_done;
    });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the polls hold both workers
  auto q = impatient(server);
  auto h = q.Get("/v1/health");
  ASSERT_TRUE(h) << "health unanswered while long polls hold every worker";
  EXPECT_EQ(h->status, 200);
  EXPECT_EQ(body_json(h)["running"], 1);
  auto d = q.Get("/v1/devices");
  ASSERT_TRUE(d);
  EXPECT_EQ(d->status, 200);
  auto s = q.Get(("/v1/jobs/" + id).c_str());
  ASSERT_TRUE(s);
  EXPECT_EQ(body_json(s)["state"], "running");
  EXPECT_EQ(polls_done.load(), 0) << "the long polls ended early: the test did not hold the workers";
  for (auto& t : polls) t.join();
  polls.clear();
  // A DELETE is not light: it waited for a worker, which the polls have now given back.
  auto del = c.Delete(("/v1/jobs/" + id).c_str());
  EXPECT_TRUE(del && del->status == 202);
  EXPECT_TRUE(wait_state(c, id, "cancelled"));
}

// Beyond the cap of connections from one address, requests get 503 naming the cap; health still
// answers (a client's monitoring shares its address with what it floods).
TEST(ServerHostile, ConnectionCapsAnswer503ButHealth) {
  TempDir dir("caps");
  ServerProcess server(dir.path,
                       {"--data", (dir.path / "data").string(), "--max-client-connections", "8", "--no-warm-up"});
  ASSERT_TRUE(server.start()) << server.error();
  std::vector<std::unique_ptr<RawSocket>> idle;
  for (int i = 0; i < 8; ++i) {
    idle.push_back(std::make_unique<RawSocket>(server.port()));
    ASSERT_TRUE(idle.back()->connected());
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the server has counted them
  auto c = impatient(server);
  auto r = c.Post("/v1/jobs", json::parse(R"({"tables": [{"kind": "ggx", "size": 4}]})").dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 503);
  EXPECT_NE(body_json(r).value("error", "").find("--max-client-connections 8"), std::string::npos) << r->body;
  EXPECT_FALSE(r->get_header_value("Retry-After").empty());
  auto h = impatient(server).Get("/v1/health");
  ASSERT_TRUE(h);
  EXPECT_EQ(h->status, 200);
  // Once they close, the client is served again.
  idle.clear();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  auto again = impatient(server).Post("/v1/jobs", json::parse(R"({"tables": [{"kind": "ggx", "size": 4}]})").dump(),
                                      "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 202) << again->body;
}

// Bodies as clients send them. curl -d and --data-binary say application/x-www-form-urlencoded:
// the body is still the JSON document, at any size up to --max-body (cpp-httplib alone refuses
// such a body past 8 KiB with a 413 that names --max-body, and parses it as a form). Chunked
// bodies and Expect: 100-continue are taken; what the API cannot read is refused with its reason.
TEST(ServerHostile, BodiesAsClientsSendThem) {
  TempDir dir("bodies");
  ServerProcess server(dir.path, {"--data", (dir.path / "data").string(), "--max-body", "64K", "--no-warm-up"});
  ASSERT_TRUE(server.start()) << server.error();
  const std::string big = job_of_bytes(20 * 1024).dump();
  ASSERT_GT(big.size(), 16u * 1024);
  auto c = server.client();
  // curl --data-binary @job.json
  auto form = c.Post("/v1/jobs", big, "application/x-www-form-urlencoded");
  ASSERT_TRUE(form);
  EXPECT_EQ(form->status, 202) << form->body;
  EXPECT_EQ(body_json(form)["tables"], json::parse(big)["tables"].size());
  // No content type at all.
  auto none = c.Post("/v1/jobs", big, "");
  ASSERT_TRUE(none);
  EXPECT_EQ(none->status, 202) << none->body;
  // Chunked (a client streaming its body), in pieces of 1000 bytes.
  {
    RawSocket s(server.port());
    std::string req = "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n\r\n";
    for (size_t at = 0; at < big.size(); at += 1000) {
      const std::string part = big.substr(at, 1000);
      char size[16];
      std::snprintf(size, sizeof size, "%zx", part.size());
      req += std::string(size) + "\r\n" + part + "\r\n";
    }
    req += "0\r\n\r\n";
    ASSERT_TRUE(s.send(req));
    const std::string reply = s.receive(10, "\"queued\"");
    EXPECT_EQ(status_of(reply), 202) << reply;
  }
  // Expect: 100-continue: the server says continue before the body is sent.
  {
    RawSocket s(server.port());
    ASSERT_TRUE(s.send("POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nExpect: 100-continue\r\nContent-Length: " +
                       std::to_string(big.size()) + "\r\n\r\n"));
    const std::string go = s.receive(5, "\r\n\r\n");
    EXPECT_EQ(status_of(go), 100) << go;
    ASSERT_TRUE(s.send(big));
    const std::string reply = s.receive(10, "\"queued\"");
    EXPECT_EQ(status_of(reply), 202) << reply;
  }
  // Larger than --max-body: 413 at once, before the body is sent.
  {
    RawSocket s(server.port());
    ASSERT_TRUE(s.send("POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 70000\r\n\r\n"));
    const std::string reply = s.receive(5, "}");
    EXPECT_EQ(status_of(reply), 413) << reply;
    EXPECT_NE(reply.find("--max-body"), std::string::npos) << reply;
  }
  // A chunked body past --max-body.
  {
    RawSocket s(server.port());
    ASSERT_TRUE(s.send("POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n\r\n11170\r\n"));
    const std::string reply = s.receive(5, "}");
    EXPECT_EQ(status_of(reply), 413) << reply;
  }
  // What the API cannot read, each with its reason.
  const std::vector<std::tuple<std::string, int, std::string>> refused = {
      {"Content-Type: multipart/form-data; boundary=x\r\nContent-Length: 10\r\n", 415, "multipart"},
      {"Content-Encoding: gzip\r\nContent-Length: 10\r\n", 415, "Content-Encoding 'gzip'"},
      {"Transfer-Encoding: gzip, chunked\r\n", 501, "Transfer-Encoding"},
      {"Content-Length: 10\r\nContent-Length: 12\r\n", 400, "Content-Length"},
      {"Content-Length: 10\r\nTransfer-Encoding: chunked\r\n", 400, "both"},
      {"Content-Length: -1\r\n", 400, "Content-Length"},
      {"Expect: magic\r\nContent-Length: 10\r\n", 417, "Expect"},
  };
  for (const auto& [headers, status, words] : refused) {
    RawSocket s(server.port());
    ASSERT_TRUE(s.send("POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\n" + headers + "\r\n0123456789"));
    const std::string reply = s.receive(5, "}");
    EXPECT_EQ(status_of(reply), status) << headers << reply;
    EXPECT_NE(reply.find(words), std::string::npos) << headers << reply;
  }
  // Headers past 64 KiB.
  {
    RawSocket s(server.port());
    (void)s.send("GET /v1/health HTTP/1.1\r\nX-Big: " + std::string(70 * 1024, 'a') + "\r\n\r\n");
    EXPECT_EQ(status_of(s.receive(5, "}")), 431);
  }
  // Keep-alive and pipelining: two requests in one write, two replies in order.
  {
    RawSocket s(server.port());
    ASSERT_TRUE(s.send(
        "GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\nGET /v1/devices HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
    const std::string replies = s.receive(5, "\"default\"");
    EXPECT_EQ(status_of(replies), 200) << replies;
    EXPECT_NE(replies.find("\"uptime_seconds\""), std::string::npos);
    EXPECT_NE(replies.find("\"devices\": ["), std::string::npos) << replies;
  }
  EXPECT_EQ(c.Get("/v1/health")->status, 200);
}

// POST /v1/tables past --table-timeout: the 504 stops the bake at its next step (a row of a
// reference table), GET /v1/devices says the device is busy with it while it bakes, and the device
// serves the next job. Before, the bake ran on for minutes (or, on the reference, took the server
// down) while /v1/devices said idle.
TEST(ServerHostile, AbandonedTableStopsItsBake) {
  TempDir dir("abandoned");
  ServerProcess server(dir.path, {"--data", (dir.path / "data").string(), "--table-timeout", "1", "--no-warm-up"});
  ASSERT_TRUE(server.start()) << server.error();
  std::atomic<int> status{0};
  std::thread table([&] {
    httplib::Client t(server.url());
    t.set_read_timeout(60, 0);
    auto r = t.Post("/v1/tables", R"({"kind": "ggx", "size": 1024, "device": "reference", "output": "big.exr"})",
                    "application/json");
    status = r ? r->status : -1;
  });
  auto c = server.client();
  struct Join {
    std::thread& t;
    ~Join() {
      if (t.joinable()) t.join();
    }
  } join{table};
  auto reference = [&]() -> json {
    auto d = c.Get("/v1/devices");
    const json all = body_json(d);
    if (!all.is_object() || !all.contains("devices")) return json::object({{"answer", d ? d->body : "none"}});
    for (const auto& e : all["devices"])
      if (e.value("key", "") == "reference") return e;
    return json::object();
  };
  bool seen_busy = false;
  for (int i = 0; i < 1500 && status == 0 && !seen_busy; ++i) {
    const json e = reference();
    seen_busy = e.value("busy", false) && e.value("table", json()) == "ggx 1024";
    if (!seen_busy) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(seen_busy) << "GET /v1/devices did not say the reference bakes the table: " << reference().dump();
  if (table.joinable()) table.join();
  EXPECT_EQ(status.load(), 504);
  // The bake stops at its next row: the device is free again long before the table could end.
  bool free = false;
  for (int i = 0; i < 600 && !free; ++i) {
    free = reference().value("busy", true) == false;
    if (!free) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(free) << "the abandoned table still holds the reference: " << reference().dump();
  auto h = c.Get("/v1/health");
  ASSERT_TRUE(h) << "the server is gone: " << server.stderr_text();
  EXPECT_EQ(body_json(h)["tables_running"], 0);
  const json small =
      wait_job(c, submit(c, json::parse(R"({"device": "reference", "tables": [{"kind": "ggx", "size": 4}]})")), 60);
  EXPECT_EQ(small["state"], "done") << small.dump();
}

// DELETE of a running job, then kill -9 before the job reaches its next step: after the restart the
// job is cancelled, not run again (the cancel was recorded when it was asked for).
TEST(ServerHostile, CancelledRunningJobIsNotRunAgain) {
  TempDir dir("cancelkill");
  const std::vector<std::string> args = {"--data", (dir.path / "data").string(), "--no-warm-up"};
  std::string id;
  {
    ServerProcess server(dir.path, args);
    ASSERT_TRUE(server.start()) << server.error();
    auto c = server.client();
    id = submit(c, reference_job());
    ASSERT_FALSE(id.empty());
    ASSERT_TRUE(wait_state(c, id, "running"));
    auto del = c.Delete(("/v1/jobs/" + id).c_str());
    ASSERT_TRUE(del);
    EXPECT_EQ(del->status, 202);
    server.signal(SIGKILL);
    EXPECT_EQ(server.wait_exit(10), -1);
  }
  ServerProcess again(dir.path, args);
  ASSERT_TRUE(again.start()) << again.error();
  auto c = again.client();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // were it re-queued, it would run now
  const json s = body_json(c.Get(("/v1/jobs/" + id).c_str()));
  EXPECT_EQ(s.value("state", ""), "cancelled") << s.dump();
  EXPECT_EQ(s.value("attempts", 0), 1) << s.dump();
  EXPECT_EQ(s.value("exit_code", 0), 1) << s.dump();
  EXPECT_FALSE(fs::exists(dir.path / "data" / "jobs" / id));
  auto d = c.Get("/v1/devices");
  ASSERT_TRUE(d);
  for (const auto& e : body_json(d)["devices"]) EXPECT_FALSE(e.value("busy", true)) << e.dump();
}

}  // namespace
}  // namespace brdfbake::test
