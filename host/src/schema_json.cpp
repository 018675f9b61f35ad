// The schemas as JSON: the one serialisation `brdfbake kinds --json` prints and the Python package
// reads (brdfbake.schema, brdfbake.plan_options), so that both spell every type the same way.
#include <cmath>
#include <nlohmann/json.hpp>

#include "brdfbake/params.hpp"
#include "brdfbake/tables.hpp"

namespace brdfbake {

namespace {

using json = nlohmann::ordered_json;

bool integral(ParamType t) { return t == ParamType::Int || t == ParamType::IntList; }

// A number of an integer parameter as a JSON integer (128, not 128.0).
json number_json(double x, ParamType t) {
  if (integral(t) && std::isfinite(x) && std::floor(x) == x && std::fabs(x) < 9.0e15) return static_cast<long long>(x);
  return x;
}

json value_json(const ParamValue& v, ParamType t) {
  if (auto b = std::get_if<bool>(&v)) return *b;
  if (auto x = std::get_if<double>(&v)) return number_json(*x, t);
  if (auto s = std::get_if<std::string>(&v)) return *s;
  json a = json::array();
  for (double x : std::get<std::vector<double>>(v)) a.push_back(number_json(x, t));
  return a;
}

bool numeric(ParamType t) {
  return t == ParamType::Int || t == ParamType::Number || t == ParamType::Color || t == ParamType::Range ||
         t == ParamType::IntList;
}

json param_json(const ParamDef& d) {
  json p;
  p["name"] = d.name;
  p["option"] = "--" + d.cli_name();
  if (!d.aliases.empty()) {
    json a = json::array();
    for (const std::string& x : d.aliases) a.push_back(spelled_name(x, true));
    p["aliases"] = a;  // other spellings every front end also accepts (old names, short ones), as options
  }
  p["type"] = param_type_name(d.type);
  p["expects"] = param_expectation(d);
  if (!d.choices.empty()) p["choices"] = d.choices;
  if (d.fallback) p["default"] = value_json(*d.fallback, d.type);
  if (!d.default_text.empty()) p["default_text"] = d.default_text;
  p["required"] = d.required;
  p["output_only"] = d.output_only;
  p["help"] = d.help;
  // The range in numbers (the "expects" text says it in words); infinite ends are left out.
  if (numeric(d.type)) {
    if (std::isfinite(d.lo)) p["min"] = number_json(d.lo, d.type);
    if (d.lo_open) p["min_exclusive"] = true;
    if (std::isfinite(d.hi)) p["max"] = number_json(d.hi, d.type);
  }
  if (d.type == ParamType::IntList) p["max_items"] = d.max_items;
  return p;
}

json schema_array(const std::vector<ParamDef>& schema) {
  json a = json::array();
  for (const ParamDef& d : schema) a.push_back(param_json(d));
  return a;
}

}  // namespace

const char* param_type_name(ParamType t) {
  switch (t) {
    case ParamType::Int:
      return "integer";
    case ParamType::Number:
      return "number";
    case ParamType::Name:
      return "name";
    case ParamType::Path:
      return "path";
    case ParamType::Flag:
      return "flag";
    case ParamType::Color:
      return "rgb";
    case ParamType::Range:
      return "range";
    case ParamType::IntList:
      return "integers";
  }
  return "?";
}

std::string schema_json(const std::vector<ParamDef>& schema, int indent) { return schema_array(schema).dump(indent); }

std::string table_kinds_json(int indent) {
  json kinds = json::array();
  for (TableKind k : table_kinds()) {
    json o;
    o["kind"] = table_kind_name(k);
    o["command"] = table_kind_command(k);
    o["summary"] = table_kind_summary(k);
    o["environment"] = table_kind_uses_environment(k);
    o["default_pixel"] = table_kind_default_pixel(k);
    o["parameters"] = schema_array(table_schema(k));
    kinds.push_back(o);
  }
  json doc;
  doc["kinds"] = kinds;
  doc["common_fields"] = table_common_fields();
  return doc.dump(indent);
}

}  // namespace brdfbake
