// brdfbake kinds [--json | --markdown]: every table kind with its parameters, from the schemas the
// job parser, the commands and the bindings share (docs/SCENES.md's table is this output).
#include <iostream>
#include <nlohmann/json.hpp>

#include "brdfbake/plan.hpp"
#include "cli_table.hpp"

namespace brdfbake::cli {

namespace {

const char* type_name(ParamType t) {
  switch (t) {
    case ParamType::Int: return "integer";
    case ParamType::Number: return "number";
    case ParamType::Name: return "name";
    case ParamType::Path: return "path";
    case ParamType::Flag: return "flag";
    case ParamType::Color: return "rgb";
    case ParamType::Range: return "range";
    case ParamType::IntList: return "integers";
  }
  return "?";
}

nlohmann::ordered_json value_json(const ParamValue& v) {
  if (auto b = std::get_if<bool>(&v)) return *b;
  if (auto x = std::get_if<double>(&v)) return *x;
  if (auto s = std::get_if<std::string>(&v)) return *s;
  return std::get<std::vector<double>>(v);
}

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

}  // namespace

int cmd_kinds(int argc, char** argv) {
  cxxopts::Options options("brdfbake kinds", "Every table kind with its parameters (the job format's reference)");
  options.add_options()("json", "as JSON")("markdown", "as the Markdown table of docs/SCENES.md")("h,help", "this help");
  const auto r = parse(options, argc, argv);
  if (help_or_stray(options, r)) return 0;
  if (r.count("json")) {
    nlohmann::ordered_json kinds = nlohmann::ordered_json::array();
    for (TableKind k : table_kinds()) {
      nlohmann::ordered_json o;
      o["kind"] = table_kind_name(k);
      o["command"] = table_kind_command(k);
      o["summary"] = table_kind_summary(k);
      o["environment"] = table_kind_uses_environment(k);
      o["default_pixel"] = table_kind_default_pixel(k);
      nlohmann::ordered_json params = nlohmann::ordered_json::array();
      for (const ParamDef& d : table_schema(k)) {
        nlohmann::ordered_json p;
        p["name"] = d.name;
        p["option"] = "--" + d.cli_name();
        p["type"] = type_name(d.type);
        p["expects"] = param_expectation(d);
        if (!d.choices.empty()) p["choices"] = d.choices;
        if (d.fallback) p["default"] = value_json(*d.fallback);
        if (!d.default_text.empty()) p["default_text"] = d.default_text;
        p["required"] = d.required;
        p["output_only"] = d.output_only;
        p["help"] = d.help;
        params.push_back(p);
      }
      o["parameters"] = params;
      kinds.push_back(o);
    }
    nlohmann::ordered_json doc;
    doc["kinds"] = kinds;
    doc["common_fields"] = table_common_fields();
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  if (r.count("markdown")) {
    std::cout << "| kind | command | parameter | expects | default | what |\n|---|---|---|---|---|---|\n";
    for (TableKind k : table_kinds())
      for (const ParamDef& d : table_schema(k))
        std::cout << "| `" << table_kind_name(k) << "` | " << table_kind_command(k) << " | `" << d.name << "` | "
                  << cell(param_expectation(d)) << " | " << cell(default_of(d)) << " | " << cell(d.help) << " |\n";
    return 0;
  }
  for (TableKind k : table_kinds()) {
    std::cout << table_kind_name(k) << " (brdfbake " << table_kind_command(k) << "): " << table_kind_summary(k) << "\n";
    for (const ParamDef& d : table_schema(k)) {
      const std::string def = default_of(d);
      std::cout << "  " << d.name << ": " << param_expectation(d) << (def.empty() ? "" : "; default " + def) << "\n";
    }
  }
  return 0;
}

}  // namespace brdfbake::cli
