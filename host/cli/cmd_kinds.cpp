// brdfbake kinds [--json | --markdown]: every table kind with its parameters, from the schemas the
// job parser, the commands and the bindings share (docs/SCENES.md's table is this output).
#include <iostream>

#include "brdfbake/plan.hpp"
#include "cli_table.hpp"

namespace brdfbake::cli {

namespace {

// A Markdown table cell: '|' would end it.
std::string cell(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string default_of(const ParamDef& d) {
  if (!d.default_text.empty()) return d.default_text;
  if (!d.fallback) return d.required ? "required" : "";
  if (auto s = std::get_if<std::string>(&*d.fallback)) return *s;
  return param_value_text(*d.fallback);
}

// " (alias: size)": the other names a parameter is taken by (docs/SCENES.md, "One name
// per meaning"), or "".
std::string aliases_of(const ParamDef& d) {
  std::string s;
  for (const std::string& a : d.aliases) s += (s.empty() ? " (alias: " : ", ") + a;
  return s.empty() ? s : s + ")";
}

}  // namespace

int cmd_kinds(int argc, char** argv) {
  cxxopts::Options options("brdfbake kinds", "Every table kind with its parameters (the job format's reference)");
  options.add_options()("json", "as JSON")("markdown", "as the Markdown table of docs/SCENES.md")("h,help",
                                                                                                  "this help");
  const auto r = parse(options, argc, argv);
  if (help_or_stray(options, r)) return 0;
  if (r.count("json")) {
    std::cout << table_kinds_json(2) << "\n";
    return 0;
  }
  if (r.count("markdown")) {
    std::cout << "| kind | command | parameter | expects | default | what |\n|---|---|---|---|---|---|\n";
    for (TableKind k : table_kinds())
      for (const ParamDef& d : table_schema(k))
        std::cout << "| `" << table_kind_name(k) << "` | " << table_kind_command(k) << " | `" << d.name << "` | "
                  << cell(param_expectation(d)) << " | " << cell(default_of(d)) << " | " << cell(d.help + aliases_of(d))
                  << " |\n";
    return 0;
  }
  for (TableKind k : table_kinds()) {
    std::cout << table_kind_name(k) << " (brdfbake " << table_kind_command(k) << "): " << table_kind_summary(k) << "\n";
    for (const ParamDef& d : table_schema(k)) {
      const std::string def = default_of(d);
      std::cout << "  " << d.name << aliases_of(d) << ": " << param_expectation(d)
                << (def.empty() ? "" : "; default " + def) << "\n";
    }
  }
  return 0;
}

}  // namespace brdfbake::cli
