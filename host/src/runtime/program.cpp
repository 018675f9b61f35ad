#include "runtime/program.hpp"

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>

#include "brdfbake/diagnostics.hpp"
#include "io/atomic_file.hpp"
#include "runtime/cache_dirs.hpp"
#include "runtime/stderr_capture.hpp"

namespace brdfbake::detail {

const std::vector<std::pair<std::string, std::string>>& embedded_kernel_sources();

namespace fs = std::filesystem;

namespace {

std::string read_kernel_file(const std::string& path) {
  if (const char* dir = std::getenv("BRDFBAKE_KERNEL_DIR"); dir && *dir) {
    const fs::path p = fs::path(dir) / path;
    std::ifstream in(p, std::ios::binary);
    if (!in) throw Error("cannot read kernel source " + p.string() + " (BRDFBAKE_KERNEL_DIR is set)");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  for (const auto& [name, text] : embedded_kernel_sources())
    if (name == path) return text;
  throw Error("no embedded kernel source named '" + path + "'");
}

// Expands #include "x" lines (paths relative to kernels/), each file at most once, and marks the
// origin of every line with #line so build logs point into the right file.
void expand(const std::string& path, std::set<std::string>& seen, std::ostringstream& out) {
  if (!seen.insert(path).second) return;
  std::istringstream in(read_kernel_file(path));
  std::string line;
  int number = 0;
  out << "#line 1 \"" << path << "\"\n";
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line.compare(first, 8, "#include") == 0) {
      const auto q1 = line.find('"', first), q2 = line.rfind('"');
      if (q1 == std::string::npos || q2 <= q1)
        throw Error("kernels/" + path + ":" + std::to_string(number) + ": only #include \"file\" is supported");
      expand(line.substr(q1 + 1, q2 - q1 - 1), seen, out);
      out << "#line " << number + 1 << " \"" << path << "\"\n";
      continue;
    }
    if (first != std::string::npos && line.compare(first, 12, "#pragma once") == 0) {
      out << "\n";
      continue;
    }
    out << line << "\n";
  }
}

std::mutex g_cache_dir_mutex;
bool g_cache_dir_set = false;
std::string g_cache_dir;

std::mutex g_observer_mutex;
ProgramBuildStartObserver g_on_start;
ProgramBuildObserver g_on_done;

void notify_start(const std::string& program, const std::string& device) {
  std::lock_guard<std::mutex> lock(g_observer_mutex);
  if (g_on_start) g_on_start(program, device);
}
void notify_done(const ProgramBuild& b) {
  std::lock_guard<std::mutex> lock(g_observer_mutex);
  if (g_on_done) g_on_done(b);
}

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

// Builds (compiles, or links a cached binary) with whatever the implementation prints to stderr
// contained; returns the OpenCL error code (CL_SUCCESS) and appends the build log and the
// contained text to *log.
cl_int contained_build(cl::Program& program, const cl::Device& device, const std::string& options, std::string* log) {
  cl_int code = CL_SUCCESS;
  const std::string printed = run_with_stderr_captured([&] {
    try {
      program.build({device}, options.c_str());
    } catch (const cl::Error& e) {
      code = e.err();
    }
  });
  std::string build_log;
  try {
    build_log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
  } catch (const cl::Error&) {
  }
  *log = trimmed(trimmed(build_log) + "\n" + trimmed(printed));
  return code;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::atomic<uint64_t> g_disk_hits{0}, g_source_builds{0}, g_bad_entries{0}, g_write_failures{0};

uint64_t fnv1a64(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

const char kMagic[] = "BRDFBAKE-PROGRAM-BINARY-2\n";

std::string cache_file(const std::string& dir, const std::string& key) {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.bin", static_cast<unsigned long long>(fnv1a64(key)));
  return (fs::path(dir) / name).string();
}

// Entry layout: magic, u64 key length, key, u64 binary length, u64 FNV-1a of the binary, binary.
// The cached binary for `key`, or "" when absent or not ours (the whole key is stored and compared,
// so a hash collision is a miss, not a wrong program). A truncated or altered entry never reaches
// the driver: its length or checksum does not match, and it counts as a bad entry.
std::string load_binary(const std::string& file, const std::string& key) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  const std::string all = s.str();
  const size_t magic = sizeof kMagic - 1;
  auto u64_at = [&](size_t at) {
    uint64_t v = 0;
    std::memcpy(&v, all.data() + at, 8);
    return v;
  };
  if (all.size() < magic + 8 || all.compare(0, magic, kMagic) != 0) {
    ++g_bad_entries;
    return {};
  }
  const uint64_t key_len = u64_at(magic);
  if (key_len > all.size() - magic - 8 || all.size() - magic - 8 - key_len < 16) {
    ++g_bad_entries;
    return {};
  }
  if (all.compare(magic + 8, key_len, key) != 0) return {};
  const uint64_t bin_len = u64_at(magic + 8 + key_len);
  const uint64_t checksum = u64_at(magic + 16 + key_len);
  const size_t bin_at = magic + 24 + key_len;
  if (bin_len == 0 || bin_len != all.size() - bin_at) {
    ++g_bad_entries;
    return {};
  }
  std::string binary = all.substr(bin_at);
  if (fnv1a64(binary) != checksum) {
    ++g_bad_entries;
    return {};
  }
  return binary;
}

void store_binary(const std::string& file, const std::string& key, const std::string& binary) {
  std::string blob(kMagic);
  const uint64_t key_len = key.size(), bin_len = binary.size(), checksum = fnv1a64(binary);
  blob.append(reinterpret_cast<const char*>(&key_len), 8);
  blob.append(key);
  blob.append(reinterpret_cast<const char*>(&bin_len), 8);
  blob.append(reinterpret_cast<const char*>(&checksum), 8);
  blob.append(binary);
  // A cache that cannot be written only costs time: said once a process.
  const std::string dir = fs::path(file).parent_path().string();
  auto failed = [&](const std::string& why) {
    ++g_write_failures;
    runtime_warning("brdfbake's kernel cache folder '" + dir + "' cannot be written (" + why +
                    "): kernels are compiled on every run (set BRDFBAKE_CACHE_DIR to choose another)");
  };
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return failed(ec.message());
  try {
    io::write_file_atomically(file, blob);
  } catch (const std::exception& e) {
    std::string why = e.what();
    const std::string head = "cannot write '" + file + "': ";
    failed(why.rfind(head, 0) == 0 ? why.substr(head.size()) : why);
  }
}

[[noreturn]] void throw_build_failure(const ProgramSpec& spec, const std::string& options, int code, std::string log) {
  if (log.empty()) log = "(no build log)";
  throw Error("building kernels/" + spec.file + " failed (" + std::to_string(code) + " " + cl_error_name(code) +
              ", options '" + options + "'):\n" + log);
}

}  // namespace

std::string kernel_source(const std::string& path) {
  std::set<std::string> seen;
  std::ostringstream out;
  expand(path, seen, out);
  return out.str();
}

std::string program_cache_dir() {
  {
    std::lock_guard<std::mutex> lock(g_cache_dir_mutex);
    if (g_cache_dir_set) return g_cache_dir;
  }
  if (const char* d = std::getenv("BRDFBAKE_CACHE_DIR")) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return (fs::path(x) / "brdfbake" / "kernels").string();
  if (const char* h = std::getenv("HOME"); h && *h) return (fs::path(h) / ".cache" / "brdfbake" / "kernels").string();
  return {};
}

void set_program_cache_dir(const std::string& dir) {
  std::lock_guard<std::mutex> lock(g_cache_dir_mutex);
  g_cache_dir_set = true;
  g_cache_dir = dir;
}

ProgramCacheStats program_cache_stats() {
  return {g_disk_hits.load(), g_source_builds.load(), g_bad_entries.load(), g_write_failures.load()};
}

cl::Program build_program(Device::Impl& dev, const ProgramSpec& spec) {
  if (spec.precision == Precision::Fp64 && !dev.info.fp64)
    throw Error("device '" + dev.info.name + "' has no fp64 support (cl_khr_fp64); use --precision fp32");

  std::ostringstream src;
  src << "// brdfbake program " << spec.file << "\n";
  if (spec.precision == Precision::Fp64) src << "#define BRDFBAKE_FP64 1\n";
  for (const auto& [name, value] : spec.defines) src << "#define " << name << " " << value << "\n";
  src << kernel_source(spec.file);
  const std::string source = src.str();
  const std::string options = "-cl-std=CL1.2 " + spec.options;

  const std::string key = "platform=" + dev.info.platform_name + "\nplatform_version=" + dev.info.platform_version +
                          "\ndevice=" + dev.info.name + "\ndevice_version=" + dev.info.version +
                          "\ndriver=" + dev.info.driver_version + "\noptions=" + options + "\nsource=\n" + source;

  std::lock_guard<std::mutex> lock(dev.programs_mutex);
  if (auto it = dev.programs.find(key); it != dev.programs.end()) return it->second;

  const std::string dir = program_cache_dir();
  const std::string file = dir.empty() ? std::string() : cache_file(dir, key);
  const std::string what = "building kernels/" + spec.file;
  const std::string label =
      "kernels/" + spec.file + " " + precision_name(spec.precision) + (spec.options.empty() ? "" : " " + spec.options);

  if (!file.empty()) {
    const std::string binary = load_binary(file, key);
    if (!binary.empty()) {
      try {
        cl::Program::Binaries bins{std::vector<unsigned char>(binary.begin(), binary.end())};
        std::vector<cl_int> status;
        const auto t0 = std::chrono::steady_clock::now();
        cl::Program program(dev.context, {dev.device}, bins, &status);
        std::string log;
        if (contained_build(program, dev.device, options, &log) != CL_SUCCESS)
          throw cl::Error(CL_BUILD_PROGRAM_FAILURE);
        ++g_disk_hits;
        notify_done({label, dev.info.name, true, seconds_since(t0), log});
        dev.programs.emplace(key, program);
        return program;
      } catch (const cl::Error&) {
        ++g_bad_entries;  // a stale or corrupt binary: build from source instead
      }
    }
  }

  notify_start(label, dev.info.name);
  const auto t0 = std::chrono::steady_clock::now();
  cl::Program program = cl_call(what, [&] { return cl::Program(dev.context, source); });
  std::string log;
  if (const cl_int code = contained_build(program, dev.device, options, &log); code != CL_SUCCESS)
    throw_build_failure(spec, options, code, log);
  ++g_source_builds;
  notify_done({label, dev.info.name, false, seconds_since(t0), log});
  if (!file.empty()) {
    try {
      const auto bins = program.getInfo<CL_PROGRAM_BINARIES>();
      if (!bins.empty() && !bins[0].empty()) store_binary(file, key, std::string(bins[0].begin(), bins[0].end()));
    } catch (const cl::Error&) {
      ++g_write_failures;
    }
  }
  dev.programs.emplace(key, program);
  return program;
}

double event_seconds(const cl::Event& event) {
  return cl_call("reading event profiling", [&] {
    const auto start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const auto end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    return static_cast<double>(end - start) * 1e-9;
  });
}

}  // namespace brdfbake::detail

namespace brdfbake {

void set_program_build_observers(ProgramBuildStartObserver on_start, ProgramBuildObserver on_done) {
  std::lock_guard<std::mutex> lock(detail::g_observer_mutex);
  detail::g_on_start = std::move(on_start);
  detail::g_on_done = std::move(on_done);
}

}  // namespace brdfbake
