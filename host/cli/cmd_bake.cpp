// brdfbake bake [--scene FILE.gltf|FILE.glb|FILE.json] [--env FILE|builtin:NAME] [-o DIR]
//               [--dry-run [--json]] [--no-energy-compensation] [...]
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "brdfbake/error_figures.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/view.hpp"
#include "cli_remote.hpp"
#include "cli_table.hpp"

namespace brdfbake::cli {

namespace {

std::string list_materials(const std::vector<std::string>& m, size_t shown = 4) {
  std::string s;
  for (size_t i = 0; i < m.size() && i < shown; ++i) s += (i ? ", " : "") + m[i];
  if (m.size() > shown) s += " and " + std::to_string(m.size() - shown) + " more";
  return s;
}

// The table's parameters; a job with an engine target prints that target in place of the table's
// own `target` (generic: the planner applies the engine's schedule and SH window itself).
std::string params_text(const TableRequest& t, const std::string& job_target = "generic") {
  std::string s;
  const auto& schema = table_schema(t.kind);
  for (const auto& p : t.params) {
    // How a file is written (a folder output's layout and image format, the f16 clamp) is said only
    // where the plan set it: at its default it describes nothing of this table (issue 34)
    if (const ParamDef* d = find_param_def(schema, p.name); d && d->output_only && !t.was_given(p.name)) continue;
    if (p.name == "target" && job_target != "generic") {
      s += (s.empty() ? "" : ", ") + std::string("target ") + job_target;
      continue;
    }
    s += (s.empty() ? "" : ", ") + p.name + " ";
    if (auto b = std::get_if<bool>(&p.value))
      s += *b ? "true" : "false";
    else if (auto d = std::get_if<double>(&p.value)) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%g", *d);
      s += buf;
    } else if (auto n = std::get_if<std::string>(&p.value))
      s += *n;
    else {
      std::string v;
      for (double x : std::get<std::vector<double>>(p.value)) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", x);
        v += (v.empty() ? "" : "/") + std::string(buf);
      }
      s += v;
    }
  }
  return s;
}

std::string human_bytes(std::uint64_t b) {
  char buf[32];
  if (b >= (1u << 20))
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(b) / double(1u << 20));
  else if (b >= 1024)
    std::snprintf(buf, sizeof buf, "%.0f KiB", double(b) / 1024.0);
  else
    std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(b));
  return buf;
}

}  // namespace

// The plan, for people: what fired, each table with the rules and materials that asked for it.
void print_plan(const Plan& plan, std::ostream& out) {
  const Job& job = plan.job;
  out << (job.scene.empty() ? std::string("no scene") : "scene " + job.scene) << ", environment " << job.environment
      << (plan.options.energy_compensation ? ", energy compensation on" : ", energy compensation off") << "\n";
  for (const auto& n : job.notes) out << "  " << n << "\n";
  if (!job.target.empty() && job.target != "generic")
    out << "target " << job.target << ": its engine file set is written beside the tables (docs/ENGINES.md)\n";
  if (!plan.rules_fired.empty()) {
    out << "rules fired:";
    for (const auto& r : plan.rules_fired) out << " " << r;
    out << "\n";
  }
  out << job.tables.size() << (job.tables.size() == 1 ? " table" : " tables") << ":\n";
  for (const auto& t : job.tables) {
    out << "  " << t.output << "  (" << table_kind_name(t.kind) << ": " << params_text(t, job.target) << ")\n";
    for (const auto& r : t.requested_by) {
      out << "      " << r.rule << ": " << r.purpose;
      if (!r.materials.empty()) out << " [" << list_materials(r.materials) << "]";
      if (!r.note.empty()) out << "; " << r.note;
      out << "\n";
    }
  }
}

// The dry run's estimate of each table's time on this device and its bytes (estimate_job), and the
// whole bake's. An estimate that cannot be made (an environment that does not read, no device) says
// why on its own line: the plan above stands.
static void print_estimate(const Job& job, std::ostream& out) {
  PlanEstimate e;
  try {
    e = estimate_job(job);
  } catch (const Error& x) {
    out << "no estimate: " << x.what() << "\n";
    return;
  }
  size_t width = 13;
  for (const auto& t : e.tables) width = std::max(width, t.output.size());
  char buf[64];
  out << "estimate on this device (measured by bakes at reduced size, "
      << (e.calibration_seconds > 0 ? "" : "cached, ");
  std::snprintf(buf, sizeof buf, "%.2f s", e.calibration_seconds);
  out << buf << "):\n";
  for (const auto& t : e.tables) {
    std::snprintf(buf, sizeof buf, "%8.2f s", t.seconds);
    out << "  " << t.output << std::string(width - t.output.size(), ' ') << buf << "  " << human_bytes(t.bytes)
        << (t.method == "scaled" ? "  (scaled from 1/2 and 1/4 size)" : "") << "\n";
  }
  if (e.environment_seconds > 0) {
    std::snprintf(buf, sizeof buf, "%8.2f s", e.environment_seconds);
    out << "  " << std::string("(environment)") << std::string(width - 13, ' ') << buf << "\n";
  }
  std::snprintf(buf, sizeof buf, "%8.2f s", e.seconds);
  out << "  " << std::string("whole bake") << std::string(width - 10, ' ') << buf << "  " << human_bytes(e.bytes)
      << (job.target != "generic" && !job.target.empty() ? " (tables; the engine's files come beside them)" : "")
      << "\n";
}

// What a run wrote, for people.
void print_manifest_summary(const Manifest& m, std::ostream& out) {
  std::uint64_t total = 0;
  size_t width = 13;
  for (const auto& f : m.files) {
    total += f.bytes;
    width = std::max(width, f.path.size());
  }
  // The engine's file set (docs/ENGINES.md), written beside the tables: sizes from the folder.
  std::vector<std::uint64_t> engine_bytes;
  bool has_gltf = false;
  for (const auto& f : m.engine_files) {
    std::error_code ec;
    const std::uintmax_t b = std::filesystem::file_size(std::filesystem::path(m.output_dir) / f, ec);
    engine_bytes.push_back(ec ? 0 : static_cast<std::uint64_t>(b));
    total += engine_bytes.back();
    has_gltf |= std::filesystem::path(f).extension() == ".gltf";
    width = std::max(width, f.size());
  }
  const std::string engine_count = m.engine_files.empty()
                                       ? std::string()
                                       : " + " + std::to_string(m.engine_files.size()) + " engine file" +
                                             (m.engine_files.size() == 1 ? "" : "s") + " (" + m.target + ")";
  char head[384];
  std::snprintf(head, sizeof head, "wrote %s: %zu file%s%s from %d bake%s, %s, in %.1f s\n", m.output_dir.c_str(),
                m.files.size(), m.files.size() == 1 ? "" : "s", engine_count.c_str(), m.bakes, m.bakes == 1 ? "" : "s",
                human_bytes(total).c_str(), m.seconds);
  out << head;
  for (const auto& f : m.files) {
    // The error figure under its kind's name (docs/CONVENTIONS.md, "Error figures")
    const char* figure = error_figure(f.kind).name;
    std::string bound = std::string(figure) + " not measured";
    if (f.error_bound) {
      char b[96];
      std::snprintf(b, sizeof b, "%s %.2g", figure, *f.error_bound);
      bound = b;
    }
    // A DFG table's lookup: what a shader's bilinear fetch between texel centres misses, beside the
    // bound of the stored values (the family's interpolation_error, edge_error)
    std::string lookup, edge;
    for (const auto& [key, value] : f.details) {
      if (key == "interpolation_error") lookup = value;
      if (key == "edge_error") edge = value;
    }
    if (!lookup.empty())
      bound += ", bilinear lookup within " + lookup + (edge.empty() ? "" : " (" + edge + " at the edges)");
    if (!f.materials.empty())
      bound += ", " + std::to_string(f.materials.size()) + (f.materials.size() == 1 ? " material" : " materials");
    char line[512];
    std::snprintf(line, sizeof line, "  %-*s  %-16s %9s  %s\n", int(width), f.path.c_str(), table_kind_name(f.kind),
                  human_bytes(f.bytes).c_str(), bound.c_str());
    out << line;
    // What a shader does with a DFG table: its kinds need different formulas.
    for (const auto& [key, value] : f.details)
      if (key == "runtime") out << "    " << std::string(width, ' ') << "runtime: " << value << "\n";
  }
  if (!m.engine_files.empty()) {
    out << "  engine files, target " << m.target
        << " (docs/ENGINES.md; delivered error: the file decoded as the engine decodes it, docs/CONVENTIONS.md):\n";
    const auto entry_of = [&m](const std::string& f) -> const EngineFileEntry* {
      for (const EngineFileEntry& e : m.engine_entries)
        if (e.path == f) return &e;
      return nullptr;
    };
    const auto error_text = [](double rms, double max) {
      char b[96];
      std::snprintf(b, sizeof b, "error_rms_rel %.2g, error_max_rel %.2g", rms, max);
      return std::string(b);
    };
    // Each file with its format; a glTF document's RGBD face PNGs as one line.
    std::vector<size_t> faces;
    std::uint64_t face_bytes = 0;
    for (size_t k = 0; k < m.engine_files.size(); ++k) {
      const std::string& f = m.engine_files[k];
      if (has_gltf && std::filesystem::path(f).extension() == ".png") {
        faces.push_back(k);
        face_bytes += engine_bytes[k];
        continue;
      }
      std::string format;
      for (const auto& [key, value] : m.engine_delivered)
        if (key == f + ": format") format = value;
      const EngineFileEntry* e = entry_of(f);
      if (format.empty() && e) format = e->format;
      if (e && e->measured) format += (format.empty() ? "" : ", ") + error_text(e->error_rms_rel, e->error_max_rel);
      char line[512];
      std::snprintf(line, sizeof line, "  %-*s  %-16s %9s%s\n", int(width), f.c_str(), "engine file",
                    human_bytes(engine_bytes[k]).c_str(), format.empty() ? "" : ("  " + format).c_str());
      out << line;
      // a chain's levels: the error of each, as the manifest's _per_level lists give it
      if (e && e->measured && e->error_rms_rel_per_level.size() > 1) {
        std::string levels;
        for (size_t l = 0; l < e->error_rms_rel_per_level.size(); ++l) {
          char b[32];
          std::snprintf(b, sizeof b, "%s%.2g", l == 0 ? "" : " ", e->error_rms_rel_per_level[l]);
          levels += b;
        }
        out << "    " << std::string(width, ' ') << "error_rms_rel per level: " << levels << "\n";
      }
    }
    if (!faces.empty()) {
      const std::string what = std::to_string(faces.size()) + " PNGs: " + m.engine_files[faces.front()] + " ... " +
                               m.engine_files[faces.back()];
      // the faces' worst: each face is its own file
      double rms = 0.0, max = 0.0;
      bool measured = false;
      for (size_t k : faces)
        if (const EngineFileEntry* e = entry_of(m.engine_files[k]); e && e->measured) {
          measured = true;
          rms = std::max(rms, e->error_rms_rel);
          max = std::max(max, e->error_max_rel);
        }
      char line[768];
      std::snprintf(line, sizeof line, "  %-*s  %-16s %9s  RGBD faces the .gltf names%s\n", int(width), what.c_str(),
                    "engine file", human_bytes(face_bytes).c_str(),
                    measured ? (", worst face " + error_text(rms, max)).c_str() : "");
      out << line;
    }
  }
  out << "  manifest.json\n";
}

int cmd_bake(int argc, char** argv) {
  cxxopts::Options options("brdfbake bake",
                           "Read a glTF scene's materials and bake the tables they call for (docs/SCENES.md)");
  options.add_options()("scene",
                        "FILE.gltf, FILE.glb or FILE.json (glTF JSON); none: the standard metallic-roughness set",
                        cxxopts::value<std::string>())(
      "environment,env",
      std::string("environment: FILE (.hdr .exr .ktx2) or builtin:studio / builtin:sun (default: ") +
          kDefaultEnvironment + ") (alias: --env)",
      cxxopts::value<std::string>())(
      "sanitize", "replace NaN, infinite and negative environment pixels instead of refusing the input")(
      "memory-budget", memory_budget_help(), cxxopts::value<std::string>())(
      "wait", "when another run is writing the output folder, wait for it (default: fail at once)")(
      "o,output", "output folder", cxxopts::value<std::string>()->default_value("out"))(
      "dry-run", "print the plan and bake nothing")(
      "json", "with --dry-run: print the plan as a job document (brdfbake run accepts it)")(
      "pixel",
      "f16 | f32 for .ktx2, .h and cube containers (default: each kind's); astc4x4 | astc6x6: the chains as ASTC HDR "
      "(targets generic, khronos-viewer)",
      cxxopts::value<std::string>())("contact-sheet",
                                     "also draw every output into OUTPUT/contact_sheet.png (brdfbake view)")(
      "preview",
      "also render the target's preview of the files: OUTPUT/preview.png, preview_splitsum.exr, preview_reference.exr, "
      "preview.json (brdfbake preview, docs/PREVIEW.md)");
  add_schema_options(options, plan_schema());
  add_common_options(options);
  add_remote_options(options);
  const auto r = parse(options, argc, argv);
  refuse_two_spellings(argc, argv, bake_option_schema());
  if (r.count("help")) {
    std::cout
        << options.help()
        << "\nexample:\n  brdfbake bake --scene ../shared/scenes/SheenChair.gltf --env builtin:sun -o sheen_chair\n";
    return 0;
  }
  if (!r.unmatched().empty()) throw UsageError("unexpected argument '" + r.unmatched().front() + "'");
  const bool dry_run = r.count("dry-run") > 0;
  const bool as_json = r.count("json") > 0;
  if (as_json && !dry_run) throw UsageError("--json prints the plan: it goes with --dry-run");
  if (dry_run && r.count("contact-sheet"))
    throw UsageError("--contact-sheet draws what a bake wrote: not with --dry-run");
  if (dry_run && r.count("preview")) throw UsageError("--preview renders what a bake wrote: not with --dry-run");
  const bool quiet = quiet_option(r);

  OptionNaming naming;
  naming.cli = true;
  const BakeOptions bake = parse_bake_options(schema_params(r, bake_option_schema()), naming);
  const PlanOptions& o = bake.plan;
  Plan plan = plan_bake(bake);
  plan.job.output_dir = r["output"].as<std::string>();
  plan.job.preview = r.count("preview") > 0;
  if (plan.job.output_dir.empty()) throw UsageError("-o must name a folder");

  if (!quiet || as_json)
    for (const auto& w : plan.job.warnings) print_warning(w);
  if (dry_run) {
    if (as_json)
      std::cout << plan_to_json(plan);
    else {
      print_plan(plan, std::cout);
      std::cout.flush();
      print_estimate(plan.job, std::cout);
    }
    return 0;
  }
  if (remote_requested(r)) {  // the server reads the environment under its input root
    if (plan.job.preview)
      throw UsageError("--preview is not sent to a server: bake there, then run brdfbake preview --bake on the folder");
    if (!quiet) print_plan(plan, std::cout);
    std::cout.flush();
    return run_remote("bake", r, "bake plan", job_to_json(plan.job), plan.job.output_dir, false, quiet);
  }
  // The inputs are checked before the plan is shown: a missing environment fails first.
  bool needs_environment = false;
  for (const auto& t : plan.job.tables) needs_environment |= table_kind_uses_environment(t.kind);
  if (needs_environment) check_environment_source(o.environment);
  if (!quiet) print_plan(plan, std::cout);
  std::cout.flush();

  ProgressLine line(quiet);
  auto progress = [&](const JobEvent& e) {
    std::string what = "[" + std::to_string(e.bake + 1) + "/" + std::to_string(e.bakes) + "] " + e.what;
    what.resize(std::max<size_t>(what.size(), 56), ' ');  // overwrite a longer previous line
    line.update(what, e.fraction);
  };
  Manifest manifest;
  try {
    RunOptions run = run_options(r.count("wait") > 0, quiet);
    run.memory_budget = memory_budget_option(r);
    manifest = run_job(plan.job, progress, run);
  } catch (...) {
    line.finish();
    throw;
  }
  line.finish();
  if (!quiet) print_manifest_summary(manifest, std::cout);
  if (!quiet && !manifest.preview_files.empty()) {
    std::string median, worst;
    for (const auto& [k, v] : manifest.preview)
      if (k == "error_rms_median")
        median = v;
      else if (k == "error_rms_max")
        worst = v;
    std::cout << "preview: " << plan.job.output_dir
              << "/preview.png (split-sum against the reference, relative RMS per "
              << "sphere: median " << median << ", worst " << worst << ")\n";
  }
  if (r.count("contact-sheet")) {
    const std::string sheet = plan.job.output_dir + "/contact_sheet.png";
    ViewOptions view;
    view.title = "brdfbake bake: " + plan.job.output_dir;
    write_contact_sheet(render_contact_sheet({plan.job.output_dir}, view), sheet);
    if (!quiet) std::cout << "contact sheet: " << sheet << "\n";
  }
  return 0;
}

}  // namespace brdfbake::cli
