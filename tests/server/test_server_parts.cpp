// The server's parts on their own: the job store's recovery policy, path confinement, the loopback
// rule. (test_server.cpp tests them again through HTTP.)
#include <gtest/gtest.h>

#include "server/confine.hpp"
#include "server/job_store.hpp"
#include "server/server.hpp"
#include "server/server_process.hpp"

namespace brdfbake::test {
namespace {

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
  EXPECT_EQ(store.get(twice)->error, "the server stopped while running it 2 times (a crash or kill); not started again");
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
  EXPECT_EQ(faces, real + "/cube/px.hdr," + real + "/cube/nx.hdr," + real + "/cube/py.hdr," + real + "/cube/ny.hdr," + real +
                       "/cube/pz.hdr," + real + "/cube/nz.hdr");
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
  for (const char* h : {"127.0.0.1", "127.1.2.3", "localhost", "::1", "[::1]"}) EXPECT_TRUE(server::is_loopback(h)) << h;
  for (const char* h : {"0.0.0.0", "::", "10.0.0.1", "127.0.0", "127.0.0.256", "127.0.0.1.5", "127.a.0.1", "example.com", ""})
    EXPECT_FALSE(server::is_loopback(h)) << h;
}

}  // namespace
}  // namespace brdfbake::test
