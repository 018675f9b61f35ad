// The pieces of docs/RELIABILITY.md below the command line: the JSON reader's limits and field
// paths, the refusal of non-finite results, the radiance headroom, the output lock, the removal of
// stale temporaries, cancellation, the sizing of device launches and the device-limit checks.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>

#include "brdfbake/cancel.hpp"
#include "brdfbake/output_lock.hpp"
#include "brdfbake/tables.hpp"
#include "families/family.hpp"
#include "io/json_input.hpp"
#include "io/merl.hpp"
#include "runtime/launch.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

long dead_pid() {
  for (long p = 4000000; p > 1000; --p)
    if (::kill(static_cast<pid_t>(p), 0) != 0 && errno == ESRCH) return p;
  return 0;
}

// ---- JSON ------------------------------------------------------------------------------------------

TEST(JsonInput, OverflowNamesTheFieldPath) {
  const std::string e = error_of([] { io::parse_json(R"({"a": [1, {"b": 1e999}]})", "doc.json"); });
  EXPECT_EQ(e, "doc.json: a[1].b: the number 1e999 is out of range (not a finite double)");
  EXPECT_NE(error_of([] { io::parse_json("-1e400", "x"); }).find("x: the document: the number -1e400"),
            std::string::npos);
}

TEST(JsonInput, DepthLimitIs64) {
  auto nested = [](int n) { return std::string(size_t(n), '[') + std::string(size_t(n), ']'); };
  EXPECT_NO_THROW(io::parse_json(nested(io::kJsonMaxDepth), "x"));
  const std::string e = error_of([&] { io::parse_json(nested(io::kJsonMaxDepth + 1), "x"); });
  EXPECT_NE(e.find("JSON nested deeper than 64 levels"), std::string::npos) << e;
  // a million levels: refused at level 65, with a short message
  const std::string deep = error_of([&] { io::parse_json(nested(1000000), "x"); });
  EXPECT_LT(deep.size(), 200u) << deep;
}

TEST(JsonInput, SizeLimitAndSyntaxErrors) {
  EXPECT_NE(error_of([] { io::parse_json(std::string(io::kJsonMaxBytes + 1, ' '), "big"); }).find("larger than 64 MiB"),
            std::string::npos);
  const std::string e = error_of([] { io::parse_json(R"({"tables": [{"kind": tru}]})", "j"); });
  EXPECT_EQ(e.rfind("j: malformed JSON: ", 0), 0u) << e;
  EXPECT_NE(e.find("(at tables[0].kind)"), std::string::npos) << e;
  EXPECT_EQ(e.find("json.exception"), std::string::npos) << e;
}

TEST(JsonInput, TheDomIsWhatTheLibraryBuilds) {
  const std::string text =
      R"({"a": [1, 2.5, -3, 18446744073709551615, true, null, "s", {"k": {}}], "b": {"c": []}, "a2": 1})";
  EXPECT_EQ(io::parse_json(text, "x"), nlohmann::ordered_json::parse(text));
  // a repeated key: the last value, as nlohmann's own parser
  EXPECT_EQ(io::parse_json(R"({"a": 1, "a": 2})", "x")["a"], 2);
}

TEST(JsonInput, ExcerptsAreShortAndNeverRecurse) {
  const auto deep = io::parse_json(std::string(60, '[') + std::string(60, ']'), "x");
  EXPECT_EQ(io::json_excerpt(deep), "an array of 1");
  EXPECT_EQ(io::json_excerpt(nlohmann::ordered_json(std::string(1000, 'a'))).size(), 2u + 40u + 3u);
  EXPECT_EQ(io::json_excerpt(nlohmann::ordered_json::object()), "an empty object");
  // text that is not UTF-8 (a path from the command line) is written, never thrown on
  EXPECT_NO_THROW(io::json_text(nlohmann::ordered_json(std::string("\xff\xfe"))));
}

TEST(JsonInput, FoldersAndMissingFilesAreNamed) {
  const fs::path d = temp_dir("read");
  EXPECT_NE(error_of([&] { io::read_text_file(d.string(), "job"); }).find("it is a folder"), std::string::npos);
  EXPECT_NE(error_of([&] { io::read_text_file((d / "none").string(), "job"); }).find("no such file"),
            std::string::npos);
}

// ---- Outputs ---------------------------------------------------------------------------------------

TEST(Outputs, NonFiniteResultsAreRefusedBeforeWriting) {
  const fs::path d = temp_dir("finite");
  TableRequest t;
  t.kind = TableKind::Ggx;
  t.output = (d / "t.exr").string();
  validate_table(t);
  Table table;
  table.width = table.height = 2;
  table.channels = {"a"};
  table.x = table.y = {0.25, 0.75};
  table.data = {0.0f, 1.0f, std::numeric_limits<float>::quiet_NaN(), 0.5f};
  BakeResult r;
  r.kind = TableKind::Ggx;
  r.artifact = table;
  const std::string e = error_of([&] { write_result(r, t, t.output); });
  EXPECT_NE(e.find("1 value that is not finite (first in cell 2)"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(d / "t.exr"));
  EXPECT_TRUE(fs::is_empty(d));

  IrradianceResult irr;
  irr.sh.order = 3;
  irr.sh.radiance.assign(27, 0.0);
  irr.sh.irradiance_over_pi.assign(27, 0.0);
  irr.sh.irradiance_over_pi[4] = HUGE_VAL;
  r.kind = TableKind::Irradiance;
  r.artifact = irr;
  TableRequest s;
  s.kind = TableKind::Irradiance;
  s.output = (d / "sh.json").string();
  validate_table(s);
  try {
    write_result(r, s, s.output);
    ADD_FAILURE() << "an infinite SH coefficient was written";
  } catch (const RuntimeFailure& f) {
    EXPECT_NE(std::string(f.what()).find("the SH coefficients"), std::string::npos) << f.what();
  }
  EXPECT_TRUE(fs::is_empty(d));
  // the SH JSON's own check, for writers that call it directly
  EXPECT_THROW(sh_to_json(irr.sh, {}), RuntimeFailure);
}

TEST(Outputs, HeadroomScalesByAPowerOfTwoOnlyAboveTheThreshold) {
  EnvImage env;
  env.rgb = {1.0f, 3.0e38f, 0.5f, 7.0f, 1.0e-6f, 0.0f};
  EnvImage storage;
  double scale = 0.0;
  const EnvImage& scaled = detail::headroom_environment(env, storage, &scale);
  EXPECT_NE(&scaled, &env);
  int e = 0;
  EXPECT_EQ(std::frexp(scale, &e), 0.5);  // a power of two
  float largest = 0.0f;
  for (size_t i = 0; i < env.rgb.size(); ++i) {
    largest = std::max(largest, scaled.rgb[i]);
    // exact: only the exponent changed (values below 2^-126 of the scale, 1e-68 of the largest here,
    // would flush to zero: far below what a float output next to 3e38 can hold)
    EXPECT_EQ(double(scaled.rgb[i]) * scale, double(env.rgb[i])) << i;
  }
  EXPECT_LE(double(largest), detail::kRadianceHeadroom);
  EXPECT_GT(double(largest), detail::kRadianceHeadroom / 2);
  // a real sun (1e5) is baked as it is
  env.rgb = {1.0f, 1.0e5f};
  EXPECT_EQ(&detail::headroom_environment(env, storage, &scale), &env);
  EXPECT_EQ(scale, 1.0);
}

// ---- The output lock and stale temporaries ---------------------------------------------------------

TEST(OutputLock, ASecondHolderIsRefusedNamingTheFirst) {
  const fs::path d = temp_dir("lock");
  const std::string target = (d / "sub" / "out").string();
  {
    OutputLock first(target, false);
    EXPECT_TRUE(fs::exists(d / "sub" / ".out.lock"));
    try {
      OutputLock second(target, false);
      ADD_FAILURE() << "two locks on one output";
    } catch (const LockedError& e) {
      EXPECT_EQ(e.pid(), static_cast<long>(::getpid()));
      EXPECT_NE(std::string(e.what()).find("(pid " + std::to_string(::getpid()) + ")"), std::string::npos) << e.what();
    }
  }
  // released: the lock file and the folder the lock made are gone
  EXPECT_FALSE(fs::exists(d / "sub"));
  OutputLock again(target, false);
}

TEST(OutputLock, WaitingTakesItWhenReleased) {
  const fs::path d = temp_dir("wait");
  const std::string target = (d / "out").string();
  auto first = std::make_unique<OutputLock>(target, false);
  long seen = -1;
  std::thread release([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    first.reset();
  });
  const auto t0 = std::chrono::steady_clock::now();
  OutputLock second(target, true, [&](long pid) { seen = pid; });
  release.join();
  EXPECT_GE(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.25);
  EXPECT_EQ(seen, static_cast<long>(::getpid()));
}

TEST(OutputLock, WaitingStopsOnCancel) {
  const fs::path d = temp_dir("cancel");
  const std::string target = (d / "out").string();
  OutputLock first(target, false);
  request_cancel(SIGTERM);
  EXPECT_THROW(OutputLock(target, true), Cancelled);
  reset_cancel();
}

TEST(StaleTemporaries, OnlyThoseOfGoneProcessesAreRemoved) {
  const fs::path d = temp_dir("stale");
  const long dead = dead_pid(), me = ::getpid();
  fs::create_directories(d / (".out.tmp-" + std::to_string(dead) + "-1") / "sub");
  std::ofstream(d / (".out.tmp-" + std::to_string(dead) + "-2")) << "x";
  fs::create_directories(d / (".out.tmp-" + std::to_string(me) + "-3"));
  fs::create_directories(d / ".out.tmp-abc-4");
  fs::create_directories(d / (".other.tmp-" + std::to_string(dead) + "-5"));
  fs::create_directories(d / (".out.tmp-" + std::to_string(dead)));  // no suffix: not ours
  EXPECT_EQ(remove_stale_temporaries((d / "out/").string()), 2);
  EXPECT_FALSE(fs::exists(d / (".out.tmp-" + std::to_string(dead) + "-1")));
  EXPECT_FALSE(fs::exists(d / (".out.tmp-" + std::to_string(dead) + "-2")));
  EXPECT_TRUE(fs::exists(d / (".out.tmp-" + std::to_string(me) + "-3")));
  EXPECT_TRUE(fs::exists(d / ".out.tmp-abc-4"));
  EXPECT_TRUE(fs::exists(d / (".other.tmp-" + std::to_string(dead) + "-5")));
  EXPECT_EQ(remove_stale_temporaries((d / "missing" / "out").string()), 0);
}

// ---- Cancellation and device work ------------------------------------------------------------------

TEST(Cancel, TheFlagThrowsWithTheSignal) {
  reset_cancel();
  EXPECT_NO_THROW(throw_if_cancelled());
  request_cancel(SIGINT);
  try {
    throw_if_cancelled();
    ADD_FAILURE();
  } catch (const Cancelled& c) {
    EXPECT_EQ(c.signal(), SIGINT);
    EXPECT_NE(std::string(c.what()).find("interrupted by SIGINT"), std::string::npos);
  }
  reset_cancel();
  EXPECT_FALSE(cancel_requested());
}

TEST(Launches, SizedFromMeasuredSpeedWithinBounds) {
  const double cost = 1000.0;
  detail::LaunchSizer s(1e12, cost);
  const size_t first = s.next();
  EXPECT_EQ(first, static_cast<size_t>(detail::kFirstLaunchUnits / cost));  // a small first launch
  // fast: grows at most 4x a step
  s.measured(first, 1e-6);
  EXPECT_EQ(s.next(), 4 * first);
  // measured speed: 1e6 items a second -> kLaunchSeconds worth
  s.measured(100000, 0.1);
  EXPECT_EQ(s.next(), static_cast<size_t>(1e6 * detail::kLaunchSeconds));
  // slow: shrinks to the target, never below one item
  s.measured(10, 100.0);
  EXPECT_EQ(s.next(), 1u);
  // never above the unit cap, however fast
  for (int k = 0; k < 40; ++k) s.measured(s.next(), 1e-9);
  EXPECT_EQ(s.next(), static_cast<size_t>(detail::kMaxLaunchUnits / cost));
  // never more than what is left
  detail::LaunchSizer small(3, 1.0);
  EXPECT_EQ(small.next(), 3u);
}

TEST(DeviceLimits, BuffersAndWorkGroupsAreCheckedWithTheDeviceNamed) {
  Device::Impl dev;
  dev.info.name = "Tiny GPU";
  dev.info.max_alloc = 1 << 20;
  dev.info.global_memory = 4 << 20;
  EXPECT_NO_THROW(detail::check_device_memory(dev, 1 << 20, 4 << 20, "x"));
  const std::string a = error_of([&] { detail::check_device_memory(dev, 2 << 20, 2 << 20, "a 512x512 table"); });
  EXPECT_NE(a.find("a 512x512 table needs 2 MiB in one buffer; device 'Tiny GPU' allows at most 1 MiB "
                   "(CL_DEVICE_MAX_MEM_ALLOC_SIZE)"),
            std::string::npos)
      << a;
  const std::string g = error_of([&] { detail::check_device_memory(dev, 1 << 20, 8 << 20, "a cube"); });
  EXPECT_NE(g.find("CL_DEVICE_GLOBAL_MEM_SIZE"), std::string::npos) << g;
  EXPECT_THROW(detail::check_device_memory(dev, 2 << 20, 2 << 20, "x"), RuntimeFailure);
}

// ---- Containers ------------------------------------------------------------------------------------

TEST(Merl, HostileHeadersAndDirectionsAreRefused) {
  std::string header(12, '\0');
  const int32_t huge[3] = {1 << 20, 1 << 20, 1 << 20};
  std::memcpy(header.data(), huge, 12);
  EXPECT_NE(error_of([&] { decode_merl(header, "m.binary"); }).find("dimensions 1048576 x 1048576"), std::string::npos);
  const int32_t merl[3] = {90, 90, 180};
  std::memcpy(header.data(), merl, 12);
  EXPECT_NE(error_of([&] { decode_merl(header, "m.binary"); }).find("12 bytes, expected 34992012"), std::string::npos);
  EXPECT_NE(error_of([&] { decode_merl("x", "m.binary"); }).find("shorter than its header"), std::string::npos);
  EXPECT_THROW(io::merl_index({NAN, 0, 1}, {0, 0, 1}), Error);
  EXPECT_THROW(io::merl_index({0, 0, 0}, {0, 0, 1}), Error);
  // opposite directions: h is undefined (NaN); a valid bin, not an int conversion of a NaN
  EXPECT_LT(io::merl_index({0, 0, 1}, {0, 0, -1}), kMerlBins);
}

}  // namespace
}  // namespace brdfbake
