#include "cli_table.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>

#include "brdfbake/error_figures.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/output_checks.hpp"
#include "brdfbake/runner.hpp"

namespace brdfbake::cli {

namespace {

// An alias as an option: "cube-size" for cube_size.
std::string alias_option(std::string a) {
  std::replace(a.begin(), a.end(), '_', '-');
  return a;
}

// The option's names for cxxopts: its one spelling (the job field's), then its aliases, and the
// one-letter alias users expect of --input.
std::string option_spec(const ParamDef& d) {
  std::string spec = d.cli_name();
  if (spec == "input") spec = "i,input";
  for (const std::string& a : d.aliases) spec += "," + alias_option(a);
  return spec;
}

// " (alias: --cube-size)" for the help of an option with aliases.
std::string aliases_text(const ParamDef& d) {
  std::string s;
  for (const std::string& a : d.aliases) s += (s.empty() ? " (alias: --" : ", --") + alias_option(a);
  return s.empty() ? s : s + ")";
}

bool negated_flag(const ParamDef& d) { return d.type == ParamType::Flag && d.fallback && std::get<bool>(*d.fallback); }

std::string option_name(const ParamDef& d) { return negated_flag(d) ? "no-" + d.cli_name() : d.cli_name(); }

std::string default_text(const ParamDef& d) {
  if (!d.default_text.empty()) return d.default_text;
  if (!d.fallback) return "";
  if (auto s = std::get_if<std::string>(&*d.fallback)) return *s;
  if (auto b = std::get_if<bool>(&*d.fallback)) return *b ? "on" : "";
  return param_value_text(*d.fallback);
}

std::string help_of(const ParamDef& d) {
  std::string h = d.help;
  if (negated_flag(d)) return "(on by default) " + h + "; this option turns it off" + aliases_text(d);
  if (d.type == ParamType::Flag) return h + aliases_text(d);
  if (!d.choices.empty()) {
    std::string c;
    for (const auto& x : d.choices) c += (c.empty() ? "" : " | ") + x;
    h += " [" + c + "]";
  } else if (d.type != ParamType::Path && d.type != ParamType::Name) {
    h += " [" + param_expectation(d) + "]";
  }
  const std::string def = default_text(d);
  if (!def.empty()) h += " (default: " + def + ")";
  if (d.required) h += " (required)";
  return h + aliases_text(d);
}

std::vector<TableKind> kinds_of(const std::string& command) {
  std::vector<TableKind> out;
  for (TableKind k : table_kinds())
    if (table_kind_command(k) == command) out.push_back(k);
  return out;
}

// The union of the kinds' schemas, in order of first appearance.
std::vector<ParamDef> union_schema(const std::vector<TableKind>& kinds) {
  std::vector<ParamDef> out;
  for (TableKind k : kinds)
    for (const auto& d : table_schema(k))
      if (!find_param_def(out, d.name)) out.push_back(d);
  return out;
}

}  // namespace

void add_schema_options(cxxopts::Options& options, const std::vector<ParamDef>& schema) {
  auto adder = options.add_options();
  for (const auto& d : schema) {
    if (d.type == ParamType::Flag) {
      adder(negated_flag(d) ? "no-" + d.cli_name() : option_spec(d), help_of(d));
    } else {
      adder(option_spec(d), help_of(d), cxxopts::value<std::string>());
    }
  }
}

Params schema_params(const cxxopts::ParseResult& r, const std::vector<ParamDef>& schema) {
  Params out;
  for (const auto& d : schema) {
    const std::string name = option_name(d);
    if (!r.count(name)) continue;
    if (d.type == ParamType::Flag) {
      out.push_back({d.name, !negated_flag(d)});
      continue;
    }
    out.push_back({d.name, parse_param_text(d, r[name].as<std::string>(), "--" + d.cli_name())});
  }
  return out;
}

void refuse_two_spellings(int argc, char** argv, const std::vector<ParamDef>& schema) {
  Params typed;  // the options of `schema` as typed, by any of their spellings (values not needed)
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--") break;
    if (a.size() < 3 || a.compare(0, 2, "--") != 0) continue;
    std::string name = a.substr(2, a.find('=') == std::string::npos ? std::string::npos : a.find('=') - 2);
    std::replace(name.begin(), name.end(), '-', '_');
    if (find_param_def_or_alias(schema, name)) typed.push_back({name, false});
  }
  try {
    canonicalize_params(typed, schema, "", true);
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

std::vector<std::string> one_letter_options(int argc, char** argv, const std::vector<ParamDef>& schema) {
  std::vector<std::string> args(argv, argv + argc);
  for (std::string& a : args)
    for (const auto& d : schema) {
      const std::string n = d.cli_name();
      if (n.size() != 1) continue;
      if (a == "--" + n)
        a = "-" + n;
      else if (a.rfind("--" + n + "=", 0) == 0)
        a = "-" + n + a.substr(4);
    }
  return args;
}

int run_table_command(const TableCommand& command, int argc, char** argv) {
  const std::vector<TableKind> kinds = kinds_of(command.name);
  const std::vector<ParamDef> schema = union_schema(kinds);
  const bool env = table_kind_uses_environment(kinds.front());
  const bool eval = table_kind_streams(kinds.front());

  cxxopts::Options options("brdfbake " + command.name, command.description);
  if (kinds.size() > 1) {
    std::string names;
    for (TableKind k : kinds) names += (names.empty() ? "" : " | ") + std::string(table_kind_name(k));
    options.add_options()("kind", "the table: " + names + " (default: " + table_kind_name(kinds.front()) + ")",
                          cxxopts::value<std::string>());
  }
  // eval streams: on the command line its input defaults to standard input.
  std::vector<ParamDef> shown = schema;
  if (eval)
    for (auto& d : shown)
      if (d.name == "input") {
        d.required = false;
        d.default_text = "-";
      }
  add_schema_options(options, shown);
  if (env)
    options.add_options()(
        "environment,env",
        std::string("environment: FILE (.hdr .exr equirect or cross, .ktx2 cube), six comma-separated "
                    "face files, a path with {face}, or builtin:studio / builtin:sun (default: ") +
            kDefaultEnvironment + ") (alias: --env)",
        cxxopts::value<std::string>())("sanitize",
                                       "replace NaN, infinite and negative pixels instead of refusing the input")(
        "memory-budget", memory_budget_help(), cxxopts::value<std::string>())(
        "wait", "a folder output: when another run is writing it, wait for it (default: fail at once)");
  options.add_options()("o,output",
                        eval
                            ? std::string("f as r,g,b rows, or float32 with --binary; - : standard output (default: -)")
                            : std::string("output file (its extension picks the format)") +
                                  (env ? ", or a folder" : ", or - with --format csv for standard output") +
                                  " (default: a name made of the kind and parameters)",
                        cxxopts::value<std::string>())("format", "output format when it cannot come from the file name",
                                                       cxxopts::value<std::string>())(
      "pixel", "f16 | f32: the texels of .ktx2, .h and cube containers (prefilter .ktx2: also astc4x4 | astc6x6)",
      cxxopts::value<std::string>());
  if (command.add_extra) command.add_extra(options);
  add_common_options(options);

  const std::vector<std::string> args = one_letter_options(argc, argv, schema);
  std::vector<char*> arg_ptrs;
  for (const std::string& a : args) arg_ptrs.push_back(const_cast<char*>(a.c_str()));
  const auto r = parse(options, argc, arg_ptrs.data());
  {
    std::vector<ParamDef> spelled = schema;  // with --environment's own alias, added above
    if (env) spelled.push_back(ParamDef("environment", ParamType::Path, "").alias("env"));
    refuse_two_spellings(argc, argv, spelled);
  }
  if (r.count("help")) {
    std::printf("%s\n", options.help().c_str());
    if (!command.example.empty()) std::printf("example:\n  %s\n", command.example.c_str());
    return 0;
  }
  if (!r.unmatched().empty()) throw UsageError("unexpected argument '" + r.unmatched().front() + "'");
  if (command.handle_extra)
    if (const std::optional<int> code = command.handle_extra(r)) return *code;
  for (const auto& e : command.extra_names)
    if (r.count(e)) throw UsageError("--" + e + " is not a table option");

  TableRequest t;
  t.kind = kinds.front();
  if (r.count("kind")) {
    t.kind = table_kind_from_name(r["kind"].as<std::string>());
    if (table_kind_command(t.kind) != command.name)
      throw UsageError("--kind must be one of the kinds of brdfbake " + command.name + " (got '" +
                       r["kind"].as<std::string>() + "')");
  }
  // Options of another kind of the same command (e.g. --sheen-visibility for --kind ggx).
  for (const auto& d : schema)
    if (r.count(option_name(d)) && !find_param_def(table_schema(t.kind), d.name))
      throw UsageError("--" + option_name(d) + " does not apply to --kind " + table_kind_name(t.kind));
  t.params = schema_params(r, table_schema(t.kind));
  t.precision = precision_option(r);
  t.device = device_option(r);
  if (r.count("format")) t.format = r["format"].as<std::string>();
  if (r.count("pixel")) t.pixel = r["pixel"].as<std::string>();
  if (env)
    t.environment = r.count("environment") ? r["environment"].as<std::string>() : std::string(kDefaultEnvironment);
  if (env && t.environment.empty()) throw UsageError("--environment must not be empty");
  if (r.count("output")) t.output = r["output"].as<std::string>();
  if (eval) {
    if (t.output.empty()) t.output = "-";
    if (!t.find("input")) t.params.push_back({"input", std::string("-")});
  }
  if (t.output == "-" && !eval) {
    if (t.format.empty()) throw UsageError("-o - writes to standard output and needs --format csv");
    if (t.format != "csv") throw UsageError("only --format csv can go to standard output");
  }
  FieldNaming naming;
  naming.cli = true;
  validate_table(t, naming);  // everything checked before any slow work
  // The outputs that stream (eval, CSV tables) may be a FIFO, a device or /dev/stdout; no output
  // may be a file the request reads (brdfbake/output_checks.hpp).
  std::string ext = std::filesystem::path(t.output).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const bool streams = eval || t.format == "csv" || (t.format.empty() && ext == ".csv");
  check_table_files(t, naming, streams);
  const bool quiet = quiet_option(r);

  TableRunOptions run;
  run.open_backend = open_backend_kept;  // kept until the process ends (keep_until_exit)
  run.lock_folder_output = true;
  const RunOptions lock = run_options(r.count("wait") > 0, quiet);
  run.wait_for_lock = lock.wait_for_lock;
  run.on_wait = lock.on_wait;
  run.stream = eval;
  run.output_may_stream = streams;
  if (env) {
    run.load.sanitize = r.count("sanitize") > 0;
    run.load.memory_budget = memory_budget_option(r);
    run.on_environment = [quiet](const EnvImage& e) {
      if (!quiet)
        for (const auto& note : e.notes) std::fprintf(stderr, "note: %s\n", note.c_str());
      if (!quiet && e.sanitize.replaced)
        std::fprintf(stderr, "sanitized '%s': replaced %zu NaN, %zu infinite and %zu negative values\n",
                     e.source.c_str(), e.sanitize.nan, e.sanitize.infinite, e.sanitize.negative);
    };
  }
  ProgressLine line(quiet);
  const std::string title = "baking " + std::string(table_kind_name(t.kind));
  run.progress = [&](double fraction, const std::string& step) {
    line.update(step.empty() ? title : title + ", " + step, fraction);
  };
  TableRun done;
  try {
    done = run_table(t, run);
  } catch (...) {
    line.finish();
    throw;
  }
  line.finish();
  if (eval) {  // streamed: no result in memory, no report
    if (!quiet) std::fprintf(stderr, "%s\n", done.result.summary.c_str());
    return 0;
  }
  for (const auto& w : done.delivery.warnings) print_warning(w);
  std::string stored;
  if (const WriteReport& written = done.delivery.report; written.error_bound) {
    // the figure under its kind's name, as the file and the manifest record it (docs/CONVENTIONS.md)
    char b[256];
    std::snprintf(b, sizeof b, "; stored values: %s %.2g (%s adds %.2g)", error_figure(t.kind).name,
                  *written.error_bound, written.encoding.c_str(), written.storage_error);
    stored = b;
  }
  if (!quiet)
    std::fprintf(stderr, "%s: %s%s\n", t.output == "-" ? "stdout" : t.output.c_str(), done.result.summary.c_str(),
                 stored.c_str());
  return 0;
}

}  // namespace brdfbake::cli
