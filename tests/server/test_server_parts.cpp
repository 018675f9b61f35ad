// The server's parts on their own: the job store's recovery policy, path confinement, the loopback
// rule. (test_server.cpp tests them again through HTTP.)
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>

#include "server/confine.hpp"
#include "server/job_store.hpp"
#include "server/reply.hpp"
#include "server/scheduler.hpp"
#include "server/server.hpp"
#include "server/server_process.hpp"
#include "server/site_policy.hpp"

namespace brdfbake::test {
namespace {

using server::DeviceCandidate;
using server::JobRecord;
using server::JobState;
using server::JobStore;
using server::Roots;

TEST(ServerParts, StoreRecoveryRequeuesOnceThenFails) {
  TempDir dir("store");
  const std::string db = (dir.path / "jobs.db").string();
  std::string once, twice, queued, done;
  {
    JobStore store(db);
    auto add = [&](std::string& id) {
      JobRecord r;
      r.device = "0:0";
      r.source = "test";
      r.job = "{}";
      r.submitted = 1.0;
      store.insert(r);
      id = r.id;
      EXPECT_EQ(id.size(), 17u);
    };
    add(once);
    add(twice);
    add(queued);
    add(done);
    store.mark_running(once, 2.0, 1);
    store.mark_running(twice, 2.0, 2);
    store.mark_running(done, 2.0, 1);
    store.finish(done, JobState::Done, 3.0, "", 0, "{\"files\": []}");
    // The process dies here: nothing is closed.
  }
  JobStore store(db);
  const auto failed = store.recover(2, 10.0);
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].id, twice);
  EXPECT_EQ(store.get(once)->state, JobState::Queued);
  EXPECT_EQ(store.get(once)->attempts, 1);
  EXPECT_EQ(store.get(twice)->state, JobState::Failed);
  EXPECT_EQ(store.get(twice)->error,
            "the server stopped while running it 2 times (a crash or kill); not started again");
  EXPECT_EQ(store.get(done)->state, JobState::Done);
  EXPECT_EQ(store.get(done)->manifest, "{\"files\": []}");
  // Queued in submission order: the re-queued one first.
  const auto q = store.queued();
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].id, once);
  EXPECT_EQ(q[1].id, queued);
  EXPECT_EQ(store.count_by_state()["failed"], 1);
  EXPECT_EQ(store.integrity_check(), "ok");
}

// A DELETE of a running job is recorded: whatever stops the server before the job stops, the next
// start cancels it instead of running it again; a database from before the record existed opens.
TEST(ServerParts, StoreKeepsACancelAcrossRestarts) {
  TempDir dir("store-cancel");
  const std::string db = (dir.path / "jobs.db").string();
  std::string killed, stopped, running;
  {
    JobStore store(db);
    auto add = [&](std::string& id) {
      JobRecord r;
      r.device = "0:0";
      r.source = "test";
      r.job = "{}";
      store.insert(r);
      id = r.id;
      store.mark_running(id, 2.0, 1);
    };
    add(killed);
    add(stopped);
    add(running);
    store.request_cancel(killed);
    store.request_cancel(stopped);
    EXPECT_TRUE(store.get(killed)->cancel_requested);
    EXPECT_FALSE(store.get(running)->cancel_requested);
    // A shutdown stops `stopped` before it honours the cancel: not re-queued, cancelled.
    EXPECT_FALSE(store.requeue(stopped, 5.0));
    EXPECT_EQ(store.get(stopped)->state, JobState::Cancelled);
    // The process dies here with `killed` and `running` running.
  }
  JobStore store(db);
  EXPECT_TRUE(store.recover(2, 10.0).empty());
  const auto k = store.get(killed);
  EXPECT_EQ(k->state, JobState::Cancelled);
  EXPECT_EQ(k->exit_code, 1);
  EXPECT_EQ(k->finished, 10.0);
  EXPECT_NE(k->error.find("does not run it again"), std::string::npos) << k->error;
  EXPECT_EQ(store.get(running)->state, JobState::Queued);
  const auto q = store.queued();
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0].id, running);
}

TEST(ServerParts, StoreOpensADatabaseWithoutTheCancelColumn) {
  TempDir dir("store-old");
  const std::string db = (dir.path / "jobs.db").string();
  {
    // The schema as version 0.2.0 first wrote it.
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &h), SQLITE_OK);
    ASSERT_EQ(
        sqlite3_exec(
            h,
            "CREATE TABLE jobs(seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE, state TEXT NOT NULL,"
            " device TEXT NOT NULL, source TEXT NOT NULL, submitted REAL NOT NULL, started REAL NOT NULL DEFAULT 0,"
            " finished REAL NOT NULL DEFAULT 0, attempts INTEGER NOT NULL DEFAULT 0, timeout REAL NOT NULL DEFAULT 0,"
            " error TEXT NOT NULL DEFAULT '', exit_code INTEGER NOT NULL DEFAULT 0, job TEXT NOT NULL,"
            " manifest TEXT NOT NULL DEFAULT '');"
            "INSERT INTO jobs(id, state, device, source, submitted, attempts, job) VALUES('jold', 'running', '0:0', "
            "'t', 1, 1, '{}');",
            nullptr, nullptr, nullptr),
        SQLITE_OK);
    sqlite3_close(h);
  }
  JobStore store(db);
  ASSERT_TRUE(store.get("jold"));
  EXPECT_FALSE(store.get("jold")->cancel_requested);
  store.request_cancel("jold");
  EXPECT_TRUE(store.recover(2, 3.0).empty());
  EXPECT_EQ(store.get("jold")->state, JobState::Cancelled);
}

// Messages leave the server without its folders: what a job wrote is named inside the job's
// folder (staging folders and temporaries taken out), inputs as requests name them.
TEST(ServerParts, PublicTextHidesServerPaths) {
  TempDir dir("public");
  fs::create_directories(dir.path / "data");
  fs::create_directories(dir.path / "in" / "maps");
  const Roots roots((dir.path / "in").string(), (dir.path / "data").string());
  const std::string data = roots.data_dir().string(), in = roots.input_root().string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"cannot write '" + data + "/jobs/.j1b129630c90fc23c.tmp-31149-170841627/big.ktx2': No space left on device",
       "cannot write 'big.ktx2': No space left on device"},
      {"cannot write '" + data + "/tmp/.brdfbake-run-31149-1/big.exr': Failed to write pixel data to image file \"" +
           data + "/tmp/.brdfbake-run-31149-1/.big.exr.tmp-31149-a329520719de9ae8\". No space left on device.",
       "cannot write 'big.exr': Failed to write pixel data to image file \"big.exr\". No space left on device."},
      {"cannot write '" + data + "/jobs/.jX.tmp-1-2/cube/.level0_px.exr.tmp-1-ff': File too large",
       "cannot write 'cube/level0_px.exr': File too large"},
      {"job database '" + data + "/jobs.db': database or disk is full",
       "job database 'jobs.db': database or disk is full"},
      {in + "/maps/sky.hdr: truncated (3 of 512 scanlines)", "maps/sky.hdr: truncated (3 of 512 scanlines)"},
      {"'" + data + "' is busy", "'" + data + "' is busy"},  // the folder alone names nothing inside it
      {"nothing of the server here", "nothing of the server here"},
  };
  for (const auto& [given, want] : cases) EXPECT_EQ(roots.public_text(given), want) << given;
}

TEST(ServerParts, RootsConfineEveryKindOfPath) {
  TempDir dir("roots");
  const fs::path in = dir.path / "in", data = dir.path / "data";
  for (const char* f : {"px", "nx", "py", "ny", "pz", "nz"}) write_file(in / "cube" / (std::string(f) + ".hdr"), "x");
  write_file(in / "env.hdr", "x");
  write_file(dir.path / "outside.hdr", "x");
  fs::create_directories(data);
  fs::create_directory_symlink(dir.path, in / "up");
  const Roots roots(in.string(), data.string());
  const std::string real = fs::canonical(in).string();
  EXPECT_EQ(roots.environment("builtin:sun", "f"), "builtin:sun");
  EXPECT_EQ(roots.environment("env.hdr", "f"), real + "/env.hdr");
  EXPECT_EQ(roots.environment(real + "/./env.hdr", "f"), real + "/env.hdr");
  const std::string faces = roots.environment("cube/{face}.hdr", "f");
  EXPECT_EQ(faces, real + "/cube/px.hdr," + real + "/cube/nx.hdr," + real + "/cube/py.hdr," + real + "/cube/ny.hdr," +
                       real + "/cube/pz.hdr," + real + "/cube/nz.hdr");
  EXPECT_EQ(roots.environment(faces, "f"), faces);  // six files, already confined
  auto refused = [&](const std::string& spec, const std::string& words) {
    try {
      roots.environment(spec, "field");
      ADD_FAILURE() << spec << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("field: ", 0), 0u) << e.what();
    }
  };
  refused("../outside.hdr", "no '..'");
  refused("cube/../../outside.hdr", "no '..'");
  refused((dir.path / "outside.hdr").string(), "outside the server's input root");
  refused("up/outside.hdr", "a symbolic link");
  refused("a.hdr,b.hdr", "six comma-separated face files");
  refused("cube/{face}.exr", "not found");
  refused("", "must not be empty");
  refused(std::string("env.hdr\0x", 9), "NUL");
  refused("cube", "is not a file");
  // Without an input root nothing but builtins.
  const Roots none("", data.string());
  EXPECT_THROW(none.environment("env.hdr", "f"), Error);
  EXPECT_EQ(none.environment("builtin:studio", "f"), "builtin:studio");
  // Files served from the data directory: inside, regular, no link on the way.
  write_file(data / "jobs" / "j1" / "a.exr", "x");
  fs::create_symlink(in / "env.hdr", data / "jobs" / "j1" / "link.exr");
  EXPECT_FALSE(roots.data_file(data / "jobs" / "j1", "a.exr").empty());
  EXPECT_TRUE(roots.data_file(data / "jobs" / "j1", "link.exr").empty());
  EXPECT_TRUE(roots.data_file(data / "jobs" / "j1", "../j1/a.exr").empty());
  EXPECT_TRUE(roots.data_file(data / "jobs" / "j1", "/etc/passwd").empty());
  EXPECT_TRUE(roots.data_file(data / "jobs" / "j1", ".").empty());
}

TEST(ServerParts, LoopbackAddresses) {
  for (const char* h : {"127.0.0.1", "127.1.2.3", "localhost", "::1", "[::1]"})
    EXPECT_TRUE(server::is_loopback(h)) << h;
  for (const char* h :
       {"0.0.0.0", "::", "10.0.0.1", "127.0.0", "127.0.0.256", "127.0.0.1.5", "127.a.0.1", "example.com", ""})
    EXPECT_FALSE(server::is_loopback(h)) << h;
}

// Content-Disposition (issue 34, class 7): a name cannot end the quoted filename and add a parameter
// (filename*= injection), and the extended form carries the exact name, percent-encoded (RFC 5987).
TEST(ServerParts, ContentDispositionCannotBeInjected) {
  EXPECT_EQ(server::content_disposition("venice_ibl.ktx"),
            "attachment; filename=\"venice_ibl.ktx\"; filename*=UTF-8''venice_ibl.ktx");
  const std::string evil = "a\"; filename*=UTF-8''evil.exe";
  const std::string h = server::content_disposition(evil);
  EXPECT_EQ(h,
            "attachment; filename=\"a__ filename*=UTF-8''evil.exe\"; "
            "filename*=UTF-8''a%22%3B%20filename%2A%3DUTF-8%27%27evil.exe");
  // exactly one quoted string and one extended parameter, whatever the name
  EXPECT_EQ(std::count(h.begin(), h.end(), '"'), 2);
  EXPECT_EQ(server::content_disposition("caf\xc3\xa9\r\n.png"),
            "attachment; filename=\"caf____.png\"; filename*=UTF-8''caf%C3%A9%0D%0A.png");
}

// Who may call (issue 34, class 4): the rules on their own; ServerSecurity.OtherSitesCannotDriveIt
// sends the same headers through HTTP.
TEST(ServerParts, SitePolicyRefusesOtherPagesAndForeignHosts) {
  using server::refuse_by_site;
  EXPECT_EQ(server::host_name_of("127.0.0.1:8737"), "127.0.0.1");
  EXPECT_EQ(server::host_name_of("[::1]:8737"), "::1");
  EXPECT_EQ(server::host_name_of("LocalHost"), "localhost");
  EXPECT_EQ(server::host_name_of("a.example:80x"), "");
  EXPECT_EQ(server::host_name_of("[::1]x"), "");
  server::SitePolicy p;
  p.listen_host = "127.0.0.1";
  // Host names: loopback's, the listen host, none other (DNS rebinding).
  for (const char* host : {"127.0.0.1:8737", "localhost:8737", "[::1]:8737", "127.0.0.1", ""})
    EXPECT_EQ(refuse_by_site(p, "GET", host, "", ""), "") << host;
  for (const char* host : {"evil.example:8737", "evil.example", "127.0.0.1.nip.io:8737", "[::1", "a b"}) {
    const std::string why = refuse_by_site(p, "GET", host, "", "");
    EXPECT_NE(why.find("is not a name of this server"), std::string::npos) << host << ": " << why;
  }
  p.allowed_hosts = {"bake.lan"};
  EXPECT_EQ(refuse_by_site(p, "GET", "bake.lan:8737", "", ""), "");
  p.check_host = false;  // a server with a token and no --allowed-hosts
  EXPECT_EQ(refuse_by_site(p, "GET", "evil.example", "", ""), "");
  p.check_host = true;
  // Writes: no Origin (command line), this server's own page, allowed origins; no other page.
  EXPECT_EQ(refuse_by_site(p, "POST", "127.0.0.1:8737", "", ""), "");
  EXPECT_EQ(refuse_by_site(p, "POST", "127.0.0.1:8737", "http://127.0.0.1:8737", "same-origin"), "");
  EXPECT_EQ(refuse_by_site(p, "DELETE", "localhost:8737", "http://LOCALHOST:8737", ""), "");
  for (const char* origin : {"http://evil.example", "http://127.0.0.1:9999", "https://127.0.0.1:8737", "null"})
    for (const char* method : {"POST", "DELETE", "PUT", "PATCH"}) {
      const std::string why = refuse_by_site(p, method, "127.0.0.1:8737", origin, "cross-site");
      EXPECT_NE(why.find("another origin"), std::string::npos) << method << " " << origin << ": " << why;
    }
  EXPECT_NE(refuse_by_site(p, "POST", "127.0.0.1:8737", "", "cross-site"), "");
  // Reads from another page are the browser's to block (no CORS headers are sent).
  EXPECT_EQ(refuse_by_site(p, "GET", "127.0.0.1:8737", "http://evil.example", "cross-site"), "");
  p.allowed_origins = {"http://localhost:3000"};
  EXPECT_EQ(refuse_by_site(p, "POST", "127.0.0.1:8737", "http://localhost:3000", "cross-site"), "");
  EXPECT_NE(refuse_by_site(p, "POST", "127.0.0.1:8737", "http://localhost:3001", "cross-site"), "");
  // A header's bytes are shown printable in the one-line message.
  EXPECT_EQ(refuse_by_site(p, "POST", "127.0.0.1:8737", "http://a\nwarning: x", "").find('\n'), std::string::npos);
  EXPECT_EQ(server::split_list(" a, ,b ,"), (std::vector<std::string>{"a", "b"}));
}

// The choice of a job's device (serve --devices, issue 36): the one that finishes it first, its
// queued work and the job at its measured rate; devices with no rate yet are left out, and with
// fewer than two measured there is no choice. Known rates and backlogs, exact times.
TEST(DeviceChoice, TheFirstToFinishWithItsQueueAndRate) {
  const std::vector<DeviceCandidate> two = {{"0:0", "gpu", 1000.0, 0.0}, {"1:0", "cpu", 100.0, 0.0}};
  std::string why;
  EXPECT_EQ(server::fastest_device(two, 500.0, &why), 0);  // 0.5 s against 5 s
  EXPECT_NE(why.find("0:0 'gpu': done in 0.5 s"), std::string::npos) << why;
  EXPECT_NE(why.find("1:0 'cpu': done in 5 s"), std::string::npos) << why;
  // the GPU's queue holds 9,800 units (9.8 s): the CPU finishes 500 first (5 s against 10.3 s)
  const std::vector<DeviceCandidate> busy = {{"0:0", "gpu", 1000.0, 9800.0}, {"1:0", "cpu", 100.0, 0.0}};
  EXPECT_EQ(server::fastest_device(busy, 500.0, &why), 1);
  EXPECT_NE(why.find("done in 10.3 s (9.8 s of queued work first)"), std::string::npos) << why;
  // equal times: the first
  const std::vector<DeviceCandidate> tie = {{"0:0", "a", 100.0, 0.0}, {"0:1", "b", 100.0, 0.0}};
  EXPECT_EQ(server::fastest_device(tie, 10.0, &why), 0);
  // a device not measured yet is left out; one measured device alone is no choice
  const std::vector<DeviceCandidate> one = {{"0:0", "gpu", 0.0, 0.0}, {"1:0", "cpu", 100.0, 0.0}};
  why.clear();
  EXPECT_EQ(server::fastest_device(one, 500.0, &why), -1);
  EXPECT_TRUE(why.empty()) << why;
  const std::vector<DeviceCandidate> three = {
      {"0:0", "gpu", 0.0, 0.0}, {"1:0", "cpu", 100.0, 0.0}, {"2:0", "cpu2", 200.0, 100.0}};
  EXPECT_EQ(server::fastest_device(three, 500.0, &why), 2);  // 3 s against 5 s
  EXPECT_NE(why.find("rate not measured yet"), std::string::npos) << why;
  // a job's work units: its tables' output bytes
  TableRequest a, b;
  a.kind = TableKind::Ggx;
  a.params = {{"size", 32.0}};
  b.kind = TableKind::Ggx;
  b.params = {{"size", 64.0}};
  validate_table(a);
  validate_table(b);
  EXPECT_EQ(server::job_work_units({a, b}), double(estimate_table_bytes(a) + estimate_table_bytes(b)));
  EXPECT_GT(server::job_work_units({b}), server::job_work_units({a}));
}

}  // namespace
}  // namespace brdfbake::test
