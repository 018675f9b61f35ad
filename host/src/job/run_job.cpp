// The job runner: each distinct table baked once through the table runner (brdfbake/runner.hpp) and
// delivered to each of its outputs, every file written into a temporary folder beside the output
// folder and moved in at the end, manifest.json last.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>

#include "brdfbake/cancel.hpp"
#include "brdfbake/engines.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/output_checks.hpp"
#include "brdfbake/output_lock.hpp"
#include "brdfbake/runner.hpp"
#include "engines/babylon_frame.hpp"
#include "families/delivery.hpp"
#include "families/family.hpp"
#include "families/preview/bake_preview.hpp"
#include "io/atomic_file.hpp"
#include "io/staging_dir.hpp"
#include "job/group_tables.hpp"
#include "text.hpp"

namespace brdfbake {

namespace detail {

std::vector<std::vector<size_t>> group_tables(Job& job) {
  for (auto& t : job.tables) {
    if (t.device.empty()) t.device = job.device;
    if (table_kind_uses_environment(t.kind) && t.environment.empty()) t.environment = job.environment;
  }
  std::vector<std::vector<size_t>> groups;
  std::map<std::string, size_t> by_key;
  for (size_t i = 0; i < job.tables.size(); ++i) {
    const std::string k = table_bake_key(job.tables[i]);
    auto it = by_key.find(k);
    if (it == by_key.end()) {
      by_key[k] = groups.size();
      groups.push_back({i});
    } else {
      groups[it->second].push_back(i);
    }
  }
  return groups;
}

}  // namespace detail

namespace {

namespace fs = std::filesystem;

using detail::join;

// A short label of a bake for progress lines: "prefilter ggx 256", "fresnel dielectric 256".
std::string bake_label(const TableRequest& t) {
  std::string what = table_kind_name(t.kind);
  for (const char* key : {"distribution", "model", "layout"})
    if (!t.text(key).empty()) what += " " + t.text(key);
  if (const char* size = table_size_param(t.kind); t.find(size))
    what += " " + std::to_string(static_cast<long long>(t.number(size)));
  return what;
}

// The request as written into the staging folder: its output and its other output files there.
TableRequest staged(const TableRequest& o, const fs::path& staging) {
  TableRequest s = o;
  s.output = (staging / fs::path(o.output).lexically_normal()).string();
  for (const auto& d : table_schema(o.kind))
    if (d.type == ParamType::Path && d.output_only && o.find(d.name))
      s.set(d.name, (staging / fs::path(o.text(d.name)).lexically_normal()).string());
  return s;
}

std::uint64_t bytes_of(const fs::path& p) {
  std::error_code ec;
  if (fs::is_directory(p, ec)) {
    std::uint64_t total = 0;
    for (const auto& e : fs::recursive_directory_iterator(p, ec))
      if (e.is_regular_file(ec)) total += static_cast<std::uint64_t>(e.file_size(ec));
    return total;
  }
  return static_cast<std::uint64_t>(fs::file_size(p, ec));
}

// The tables whose kind this build cannot bake, each named with why; empty when every one can.
std::vector<std::string> unavailable_tables(const Job& job) {
  std::vector<std::string> missing;
  for (size_t i = 0; i < job.tables.size(); ++i) {
    std::string why;
    if (!table_kind_available(job.tables[i].kind, &why)) {
      std::string who;
      for (const auto& r : job.tables[i].requested_by) who += (who.empty() ? ", requested by " : " and ") + r.rule;
      missing.push_back("tables[" + std::to_string(i) + "] (" + table_kind_name(job.tables[i].kind) + " '" +
                        job.tables[i].output + "'" + who + "): " + why);
    }
  }
  return missing;
}

// The manifest's entry of the file `o` asks for: the parameters as baked (the request's, with what
// the family resolved; output parameters as asked), the device, the bound the file records with its
// parts (each rounded up as the file records them), and what writing it added.
ManifestFile manifest_entry(const TableRequest& o, const BakeResult& r, const WriteReport& written,
                            Precision precision) {
  ManifestFile f;
  f.path = fs::path(o.output).lexically_normal().string();
  f.kind = o.kind;
  f.params = o.params;
  for (const auto& p : r.parameters) {
    const ParamDef* d = find_param_def(table_schema(o.kind), p.name);
    if (!(d && d->output_only)) {
      auto it = std::find_if(f.params.begin(), f.params.end(), [&](const Param& q) { return q.name == p.name; });
      if (it != f.params.end())
        it->value = p.value;
      else
        f.params.push_back(p);
    }
  }
  f.precision = precision;
  f.device = r.device;
  if (table_kind_uses_environment(o.kind)) f.environment = o.environment;
  f.error_bound = written.error_bound ? written.error_bound : r.error_bound;
  f.error_bound_definition = r.error_bound_definition;
  f.details = r.details;
  if (written.error_bound && r.error_bound) {
    f.error_bound_definition =
        "bound on |stored value - converged value|: the integration bound plus the "
        "storage error measured on the stored values";
    f.details.push_back({"integration_error_bound", detail::bound_text(*r.error_bound)});
    f.details.push_back({"integration_error_bound_definition", r.error_bound_definition});
    f.details.push_back({"storage_error", detail::bound_text(written.storage_error)});
    f.details.push_back({"storage_encoding", written.encoding});
  }
  for (const auto& d : written.details) f.details.push_back(d);
  f.requested_by = o.requested_by;
  f.materials = o.materials();
  return f;
}

// The engine's files beside the tables (bake --target), named `name` (the folder's name, as cmgen -x
// names them, unless the run names them), from the job's first GGX chain, first Charlie chain (the
// targets that load one: khronos-viewer's NAME_charlie.ktx2) and first SH, staged in `staged`.
struct EngineInputs {
  std::optional<BakeResult> ggx_chain, charlie_chain, irradiance;
  std::string chain_pixel;  // the GGX chain's table's pixel: astc4x4 / astc6x6 make the engine's KTX2 ASTC
};
void add_engine_files(Manifest& manifest, EngineTarget engine, const Job& job, const std::string& origin,
                      const EngineInputs& in, const std::string& name, const fs::path& staged) {
  const std::optional<BakeResult>& ggx_chain = in.ggx_chain;
  const std::optional<BakeResult>& irradiance = in.irradiance;
  if (!ggx_chain || !irradiance)
    throw Error(origin + ": target: '" + job.target +
                "' needs a GGX prefiltered chain and an irradiance table in the "
                "job (the plan of brdfbake bake --target " +
                job.target + " has both)");
  EngineBake eb;
  eb.prefiltered = ggx_chain->cube();
  eb.sh = &irradiance->irradiance()->sh;
  if (irradiance->irradiance()->cube.level_count() > 0) eb.irradiance_cube = &irradiance->irradiance()->cube;
  if (in.charlie_chain) eb.charlie = in.charlie_chain->cube();
  EngineWriteOptions wo;
  wo.name = name;
  wo.gltf_scene = detail::parse_gltf_scene(job.gltf_scene, origin + ": gltf_scene");
  if (in.chain_pixel == "astc4x4" || in.chain_pixel == "astc6x6") {
    wo.astc = in.chain_pixel == "astc4x4" ? AstcBlock::Astc4x4 : AstcBlock::Astc6x6;
    wo.astc_quality = detail::kAstcQuality;
  }
  const EngineWriteResult w = write_engine_files(engine, eb, staged.string(), wo);
  manifest.target = job.target;
  for (const auto& f : w.files) manifest.engine_files.push_back(fs::path(f).lexically_relative(staged).string());
  manifest.engine_delivered = w.delivered;
  manifest.engine_entries = w.entries;
}

// The job as run_job takes it, or Error: valid, with an output folder and every kind bakeable in
// this build (before anything starts). Returns the name messages give it.
std::string check_job(Job& job) {
  validate_job(job);  // a preview's needs included (check_bake_preview)
  const std::string origin = job.source.empty() ? std::string("job") : job.source;
  if (job.output_dir.empty()) throw Error(origin + ": output_dir: missing (the folder to write into)");
  const std::vector<std::string> missing = unavailable_tables(job);
  if (!missing.empty())
    throw NotAvailableError(origin + ": not available in this build: " + join(missing, "; ") + "; nothing was written");
  return origin;
}

using BackendFor = std::function<Backend&(const std::string& selector)>;

// Environments first (a bad file fails before any device work), each loaded once, while the
// devices that will read them open.
std::map<std::string, EnvImage> load_job_environments(const Job& job, const RunOptions& options,
                                                      const BackendFor& backend_for) {
  for (const auto& t : job.tables)
    if (table_kind_uses_environment(t.kind) && table_needs_device(t)) backend_for(t.device).prepare();
  std::map<std::string, EnvImage> environments;
  EnvLoadOptions load;
  load.sanitize = job.sanitize;
  load.memory_budget = options.memory_budget;
  for (const auto& t : job.tables)
    if (table_kind_uses_environment(t.kind) && !environments.count(t.environment))
      environments.emplace(t.environment, load_environment(t.environment, load));
  return environments;
}

// The manifest's header: the job, its scene, notes and warnings (the environments' among them).
Manifest start_manifest(const Job& job, const std::string& origin, size_t bakes,
                        const std::map<std::string, EnvImage>& environments) {
  Manifest manifest;
  manifest.output_dir = job.output_dir;
  manifest.job_source = origin;
  manifest.scene = job.scene;
  manifest.notes = job.notes;
  manifest.warnings = job.warnings;
  manifest.bakes = static_cast<int>(bakes);
  for (const auto& [name, env] : environments)
    for (const auto& note : env.notes) manifest.notes.push_back("environment " + note);  // e.g. sRGB decoded
  for (const auto& [name, env] : environments)
    if (env.sanitize.replaced) manifest.warnings.push_back(sanitized_warning(name, env));
  return manifest;
}

// What an engine's file set is made of: the first GGX chain, the first Charlie chain, the first SH.
void keep_engine_input(EngineInputs& in, const TableRequest& t, const BakeResult& r) {
  if (!in.ggx_chain && r.cube() && t.text("distribution") == "ggx") {
    in.ggx_chain = r;
    in.chain_pixel = t.pixel;  // the chain's requested texels (astc4x4 / astc6x6 reach the engine's KTX2)
  }
  if (!in.charlie_chain && r.cube() && t.text("distribution") == "charlie") in.charlie_chain = r;
  if (!in.irradiance && r.irradiance()) in.irradiance = r;
}

// The inputs of group g's bake: its environment, which the last bake that reads it may free once it
// has its cube (not when a preview reads it after the tables).
BakeInputs group_inputs(const Job& job, const std::vector<std::vector<size_t>>& groups, size_t g,
                        std::map<std::string, EnvImage>& environments) {
  BakeInputs inputs;
  const TableRequest& t = job.tables[groups[g].front()];
  if (!table_kind_uses_environment(t.kind)) return inputs;
  EnvImage& env = environments.at(t.environment);
  inputs.environment = &env;
  bool read_later = false;
  for (size_t h = g + 1; h < groups.size(); ++h) {
    const TableRequest& later = job.tables[groups[h].front()];
    read_later = read_later || (table_kind_uses_environment(later.kind) && later.environment == t.environment);
  }
  if (!read_later && !job.preview) inputs.release_environment = [&env] { std::vector<float>().swap(env.rgb); };
  return inputs;
}

// One group's result delivered to each of its outputs in the staging folder, each with its manifest
// entry; `report(k)` before output k. Messages name the file the user asked for, not its staged copy.
void deliver_group(const Job& job, const std::vector<size_t>& group, int bake, const BakeResult& r,
                   const Backend& backend, const std::string& target, const fs::path& staging,
                   const RunOptions& options, const std::function<void(size_t)>& report, Manifest& manifest) {
  for (size_t k = 0; k < group.size(); ++k) {
    const TableRequest& o = job.tables[group[k]];
    report(k);
    const TableRequest s = staged(o, staging);
    const auto final_name = [&](std::string text) {
      const std::string final_path = (fs::path(target) / o.output).lexically_normal().string();
      for (size_t at = text.find(s.output); at != std::string::npos; at = text.find(s.output, at + final_path.size()))
        text.replace(at, s.output.size(), final_path);
      return text;
    };
    Delivery delivered;
    try {
      delivered = deliver_result(r, s, TableDelivery::File);
    } catch (const Cancelled&) {
      throw;
    } catch (const RuntimeFailure&) {
      throw;
    } catch (const Error& e) {
      throw Error(final_name(e.what()));  // a value the format cannot hold
    }
    ManifestFile f = manifest_entry(o, r, delivered.report, backend.result_precision(o.precision));
    for (const auto& w : delivered.warnings) {
      manifest.warnings.push_back(final_name(w));
      if (options.on_warning) options.on_warning(final_name(w));
    }
    f.bytes = bytes_of(s.output);
    f.seconds = k == 0 ? r.seconds : 0.0;
    f.bake = bake;
    manifest.files.push_back(std::move(f));
  }
}

}  // namespace

Manifest run_job(const Job& in, const JobProgress& progress, const RunOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  Job job = in;
  const std::string origin = check_job(job);
  const std::vector<std::vector<size_t>> groups = detail::group_tables(job);

  std::string target = job.output_dir;
  while (target.size() > 1 && target.back() == '/') target.pop_back();  // "out/" is the folder "out"
  check_job_files(job, target,
                  options.engine_name);  // outputs as a set, against the folder and the inputs, before any work
  // One run at a time per folder; then what killed runs left beside it can go.
  OutputLock lock(target, options.wait_for_lock, options.on_wait);
  remove_stale_temporaries(target);
  io::StagingDir staging{fs::path(target)};

  std::map<std::string, std::shared_ptr<Backend>> backends;
  const BackendFor backend_for = [&](const std::string& selector) -> Backend& {
    auto it = backends.find(selector);
    if (it == backends.end())
      it = backends.emplace(selector, options.backend ? options.backend(selector) : Backend::open(selector)).first;
    return *it->second;
  };
  // Every table's device, and what it can do, before anything slow (reading environments).
  for (const auto& g : groups) check_backend(job.tables[g.front()], backend_for(job.tables[g.front()].device));

  std::map<std::string, EnvImage> environments = load_job_environments(job, options, backend_for);
  Manifest manifest = start_manifest(job, origin, groups.size(), environments);

  const EngineTarget engine = engine_target_from_name(job.target);
  EngineInputs engine_inputs;
  // Progress: each table's bake reports [0, kBakeShare) and the writing of its files the rest, so
  // that 100 % means its files are written (encoding and the storage error measurement took up to a
  // second a table, measured); an engine's file set is one more step of its own, after the tables
  // (Babylon's .env: 1.5 s of PNG encoding under SheenChair at 256^2).
  constexpr double kBakeShare = 0.9;
  const int steps = static_cast<int>(groups.size()) + (engine != EngineTarget::Generic ? 1 : 0);
  for (size_t g = 0; g < groups.size(); ++g) {
    const TableRequest& t = job.tables[groups[g].front()];
    const std::string what = bake_label(t);
    auto report = [&](double fraction, const std::string& step) {
      throw_if_cancelled();
      if (progress) progress({int(g), steps, step.empty() ? what : what + ": " + step, fraction});
    };
    if (options.checkpoint) options.checkpoint();
    report(0.0, "");
    Backend& backend = backend_for(t.device);
    TableRunOptions bake;
    bake.delivery = TableDelivery::Memory;  // each output of the group is delivered below
    bake.backend = &backend;
    bake.inputs = group_inputs(job, groups, g, environments);
    bake.inputs.scratch_dir = staging.path().string();  // removed before the commit; with the staging on a kill
    bake.progress = [&](double fraction, const std::string& step) { report(kBakeShare * fraction, step); };
    bake.stop_requested = options.stop_requested;
    const BakeResult r = run_table(t, bake).result;
    if (engine != EngineTarget::Generic) keep_engine_input(engine_inputs, t, r);
    deliver_group(
        job, groups[g], static_cast<int>(g), r, backend, target, staging.path(), options,
        [&](size_t k) {
          report(kBakeShare + (1.0 - kBakeShare) * double(k) / double(groups[g].size()),
                 "writing " + job.tables[groups[g][k]].output);
        },
        manifest);
    report(1.0, "");  // its files are written
  }

  if (engine != EngineTarget::Generic) {
    if (progress) progress({steps - 1, steps, "writing the " + job.target + " files", 0.0});
    const std::string name = !options.engine_name.empty() ? options.engine_name
                             : !job.engine_name.empty()   ? job.engine_name
                                                          : fs::path(target).filename().string();
    add_engine_files(manifest, engine, job, origin, engine_inputs, name, staging.path());
    if (progress) progress({steps - 1, steps, "writing the " + job.target + " files", 1.0});
  }

  if (job.preview) {
    if (progress) progress({steps - 1, steps, "preview", 0.0});
    const TableRequest& chain = detail::preview::bake_preview_chain(job);
    detail::preview::write_bake_preview(job, staging.path().string(), manifest, backend_for(chain.device),
                                        environments.at(chain.environment));
  }
  if (options.checkpoint) options.checkpoint();
  manifest.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  throw_if_cancelled();  // the last moment a stop leaves the folder as it was
  io::write_file_atomically((staging.path() / "manifest.json").string(), manifest_to_json(manifest));
  staging.commit("manifest.json");
  return manifest;
}

}  // namespace brdfbake
