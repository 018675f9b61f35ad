// The runner (brdfbake/runner.hpp): one request to its delivery, for every front end.
#include "brdfbake/runner.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "brdfbake/cancel.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/output_lock.hpp"
#include "families/delivery.hpp"

namespace brdfbake {

namespace {

namespace fs = std::filesystem;

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// An environment kind's output that validation accepted as a folder of images (not a container or
// the SH JSON).
bool is_folder_output(const TableRequest& t) {
  if (!table_kind_uses_environment(t.kind)) return false;
  const std::string ext = lower_extension(t.output);
  return !(ext == ".json" || ext == ".ktx2" || ext == ".ktx" || ext == ".dds");
}

// A path whose writability stands for the output: a folder output is probed where it will be made.
std::string output_probe(const TableRequest& t) {
  if (!is_folder_output(t)) return t.output;
  std::error_code ec;
  if (fs::is_directory(t.output, ec)) return (fs::path(t.output) / "probe").string();
  std::string d = t.output;
  while (d.size() > 1 && d.back() == '/') d.pop_back();
  return d;
}

// `text` with every `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  if (from.empty()) return text;
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in && !in.eof()) throw RuntimeFailure("cannot read back '" + path.string() + "'");
  return bytes.str();
}

// A scratch folder of this process, removed with everything in it when the delivery ends.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& base) {
    static std::atomic<unsigned long long> counter{0};
    const fs::path root = base.empty() ? fs::temp_directory_path() : fs::path(base);
    path_ = root / (".brdfbake-run-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::error_code ec;
    fs::create_directories(path_, ec);
    if (ec) throw RuntimeFailure("cannot create the scratch folder '" + path_.string() + "': " + ec.message());
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// The output's bytes made in memory where the family makes them there (a table as .exr, .ktx2, .csv
// or .h, and no second output file); else written into a scratch folder and every file read back.
// Messages and warnings name the output as the request does.
Delivery deliver_bytes(const BakeResult& result, const TableRequest& t, const std::string& scratch_dir) {
  bool sidecar = false;
  for (const auto& d : table_schema(t.kind))
    if (d.type == ParamType::Path && d.output_only && t.find(d.name)) sidecar = true;
  if (!sidecar) {
    std::optional<detail::WrittenBytes> memory = detail::write_result_bytes(result, t);
    if (memory) {
      Delivery d;
      d.to = TableDelivery::Bytes;
      d.report = std::move(memory->report);
      d.files.push_back({fs::path(t.output).filename().string(), std::move(memory->bytes)});
      return d;
    }
  }
  const ScratchDir scratch(scratch_dir);
  TableRequest w = t;
  const fs::path name = fs::path(t.output).filename();
  w.output = (scratch.path() / name).string();
  // Other files the request writes (a sidecar such as sh_json) go beside it.
  for (const auto& d : table_schema(t.kind))
    if (d.type == ParamType::Path && d.output_only && t.find(d.name))
      w.set(d.name, (scratch.path() / fs::path(t.text(d.name)).filename()).string());
  const std::string scratch_prefix = scratch.path().string() + "/";
  const auto as_requested = [&](const std::string& text) {
    return replaced(replaced(text, w.output, t.output), scratch_prefix, "");
  };
  Delivery d;
  d.to = TableDelivery::Bytes;
  try {
    d.report = write_result(result, w, w.output);
  } catch (const Cancelled&) {
    throw;
  } catch (const RuntimeFailure&) {
    throw;  // I/O and device failures keep their type (and the path the system refused)
  } catch (const Error& e) {
    throw Error(as_requested(e.what()));  // a value the format cannot hold, named as the user wrote it
  }
  for (auto& warning : d.report.warnings) warning = as_requested(warning);
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(scratch.path(), ec))
    if (e.is_regular_file(ec)) files.push_back(e.path());
  std::sort(files.begin(), files.end(), [&](const fs::path& a, const fs::path& b) {
    const bool first_a = a == fs::path(w.output), first_b = b == fs::path(w.output);
    return first_a != first_b ? first_a : a < b;
  });
  for (const auto& f : files) d.files.push_back({f.lexically_relative(scratch.path()).string(), read_bytes(f)});
  return d;
}

// Throws Cancelled on the calling thread when this run was asked to stop.
BakeProgress with_stop(const TableRunOptions& o) {
  if (!o.stop_requested) return o.progress;
  const std::thread::id caller = std::this_thread::get_id();
  return [&o, caller](double fraction, const std::string& step) {
    // Reference backends report from worker threads, which must not throw: they stop by themselves.
    if (std::this_thread::get_id() == caller && o.stop_requested())
      throw Cancelled("cancelled: the run was stopped", 0);
    if (o.progress) o.progress(fraction, step);
  };
}

}  // namespace

std::string sanitized_warning(const std::string& environment, const EnvImage& image) {
  if (!image.sanitize.replaced) return "";
  return "environment '" + environment + "' sanitized: replaced " + std::to_string(image.sanitize.nan) + " NaN, " +
         std::to_string(image.sanitize.infinite) + " infinite and " + std::to_string(image.sanitize.negative) +
         " negative values";
}

Delivery deliver_result(const BakeResult& result, const TableRequest& t, TableDelivery to,
                        const std::string& scratch_dir) {
  Delivery d;
  switch (to) {
    case TableDelivery::Memory:
      d.to = to;
      break;
    case TableDelivery::File:
      d.to = to;
      d.report = write_result(result, t, t.output);
      break;
    case TableDelivery::Bytes:
      d = deliver_bytes(result, t, scratch_dir);
      break;
  }
  // A file's bound is what it records; values in memory are within the result's own.
  d.error_bound = d.report.error_bound ? d.report.error_bound : result.error_bound;
  if (d.error_bound) d.error_bound_text = error_bound_text(*d.error_bound);
  d.warnings = result.warnings;  // the values' own, then the file's
  d.warnings.insert(d.warnings.end(), d.report.warnings.begin(), d.report.warnings.end());
  return d;
}

TableRun run_table(const TableRequest& t, const TableRunOptions& o) {
  const bool file = o.delivery == TableDelivery::File;
  const bool streaming = file && o.stream && table_kind_streams(t.kind) && !o.inputs.pairs;
  // Everything that can be checked is, before any slow work.
  if (file && o.check_output && t.output != "-") check_output_path(output_probe(t), o.output_may_stream);
  // The OpenCL platform opens on a second thread (PoCL loads LLVM: ~15 ms) while the output folder
  // is locked and the inputs are read; work that needs no device (SH alone) loads no OpenCL at all.
  std::shared_ptr<Backend> owned;
  Backend* backend = o.backend;
  if (!backend) {
    owned = o.open_backend ? o.open_backend(t.device) : Backend::open(t.device);
    backend = owned.get();
  }
  if (!streaming && table_needs_device(t)) backend->prepare();
  // A cube written as a folder of images is one output of many files: one run at a time writes it
  // (docs/RELIABILITY.md, "Outputs"), and what killed runs left beside it goes.
  std::optional<OutputLock> lock;
  if (file && o.lock_folder_output && is_folder_output(t)) {
    lock.emplace(t.output, o.wait_for_lock, o.on_wait);
    remove_stale_temporaries(t.output);
  }
  check_backend(t, *backend);  // before the environment is read

  TableRun run;
  const auto since = [](std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const auto t0 = std::chrono::steady_clock::now();
  BakeInputs inputs = o.inputs;
  if (inputs.scratch_dir.empty()) inputs.scratch_dir = o.scratch_dir;
  EnvImage environment;
  if (table_kind_uses_environment(t.kind) && !inputs.environment) {
    environment = load_environment(t.environment, o.load);
    if (o.on_environment) o.on_environment(environment);
    const std::string w = sanitized_warning(t.environment, environment);
    if (!w.empty()) run.warnings.push_back(w);
    inputs.environment = &environment;
    // the pixels go once the bake has its cube (metadata stays): a 4k map holds 96 MiB
    inputs.release_environment = [&environment] { std::vector<float>().swap(environment.rgb); };
  }

  if (streaming) {
    const EvalStreamResult s = eval_stream(t, *backend, t.text("input"), t.output);
    run.result.kind = t.kind;
    run.result.device = backend->name();
    run.result.summary = s.summary;
    run.result.device_seconds = s.device_seconds;
    run.delivery.to = TableDelivery::File;
    return run;
  }
  run.input_seconds = since(t0);
  run.result = bake_table(t, *backend, inputs, with_stop(o));
  run.bake_seconds = run.result.seconds;
  environment = EnvImage{};  // the input's pixels are no longer needed
  const auto t1 = std::chrono::steady_clock::now();
  run.delivery = deliver_result(run.result, t, o.delivery, o.scratch_dir);
  run.deliver_seconds = since(t1);
  for (const auto& w : run.delivery.warnings) run.warnings.push_back(w);
  return run;
}

}  // namespace brdfbake
