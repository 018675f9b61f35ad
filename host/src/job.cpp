// Jobs: parsing and validation (every error names the document and the field), the plan and the
// manifest as JSON, and the runner: each distinct table baked once, every file written into a
// temporary folder beside the output folder and moved in at the end, manifest.json last.
//
// The runner reaches the table families through one adapter per kind (the "Adapters" section):
// each turns a TableRequest into the family's own spec, checks it with the family's validator, and
// bakes it. Those are the only lines that know the families' headers.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>

#include "brdfbake/environment.hpp"
#include "brdfbake/fresnel.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/lut.hpp"
#include "brdfbake/version.hpp"
#include "io/atomic_file.hpp"
#include "thin_film.hpp"

namespace brdfbake {

namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

std::string num(double v, const char* f = "%.9g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

const std::pair<const char*, TableKind> kKindNames[] = {
    {"ggx", TableKind::Ggx},           {"ggx-multiscatter", TableKind::GgxMultiscatter},
    {"charlie", TableKind::Charlie},   {"fresnel", TableKind::Fresnel},
    {"thin-film", TableKind::ThinFilm}, {"prefilter", TableKind::Prefilter},
    {"irradiance", TableKind::Irradiance}};

bool is_dfg(TableKind k) { return k == TableKind::Ggx || k == TableKind::GgxMultiscatter || k == TableKind::Charlie; }
bool is_image_table(TableKind k) { return is_dfg(k) || k == TableKind::Fresnel || k == TableKind::ThinFilm; }
bool uses_environment(TableKind k) { return k == TableKind::Prefilter || k == TableKind::Irradiance; }

// ---- Parameter schemas -------------------------------------------------------------------------

enum class PType { Int, Number, Name, Flag, Rgb };

struct PDef {
  std::string name;
  PType type;
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  std::vector<std::string> choices;  // Name: the accepted values (empty: any)
  std::optional<ParamValue> fallback;  // the default; none: optional, absent unless given
};

// The largest size a job accepts for any axis (the families check their own, smaller limits).
constexpr double kMaxAxis = 65536;

const std::vector<PDef>& schema(TableKind kind) {
  static const std::vector<PDef> dfg = {
      {"size", PType::Int, 1, kMaxAxis, {}, 128.0},
      {"height", PType::Int, 1, kMaxAxis, {}, std::nullopt},  // default: size
      {"samples", PType::Int, 1, 1 << 24, {}, std::nullopt},
      {"max_error", PType::Number, 0, 1, {}, std::nullopt},
      {"estimator", PType::Name, 0, 0, {"quadrature", "vndf", "ndf", "uniform"}, std::string("quadrature")},
  };
  static const std::vector<PDef> charlie = [] {
    std::vector<PDef> s = dfg;
    s.push_back({"sheen_visibility", PType::Name, 0, 0, {"estevez-kulla", "neubelt"}, std::string("estevez-kulla")});
    return s;
  }();
  static const std::vector<PDef> fresnel = {
      {"model", PType::Name, 0, 0, {}, std::nullopt},  // required; the Fresnel module names them
      {"material", PType::Name, 0, 0, {}, std::nullopt},
      {"ior", PType::Rgb, 0, 1000, {}, std::nullopt},
      {"ior_outside", PType::Number, 0, 1000, {}, std::nullopt},
      {"f0", PType::Rgb, 0, 1, {}, std::nullopt},
      {"f90", PType::Rgb, 0, 1, {}, std::nullopt},
      {"n", PType::Rgb, 0, 1000, {}, std::nullopt},
      {"k", PType::Rgb, 0, 1000, {}, std::nullopt},
      {"size", PType::Int, 1, kMaxAxis * 256, {}, 256.0},
      {"endpoints", PType::Flag, 0, 0, {}, false},
      {"vs_exact", PType::Flag, 0, 0, {}, false},
  };
  static const std::vector<PDef> thin_film = {
      {"film_ior", PType::Number, 1, 10, {}, 1.3},
      {"base_ior", PType::Number, 1, 10, {}, std::nullopt},
      {"base_f0", PType::Rgb, 0, 1, {}, std::nullopt},
      {"outside_ior", PType::Number, 1, 10, {}, 1.0},
      {"thickness_min", PType::Number, 0, 1e5, {}, 100.0},
      {"thickness_max", PType::Number, 0, 1e5, {}, 400.0},
      {"size", PType::Int, 1, 8192, {}, 128.0},
      {"height", PType::Int, 1, 8192, {}, std::nullopt},  // default: size (1 for one thickness)
  };
  static const std::vector<PDef> prefilter = {
      {"distribution", PType::Name, 0, 0, {"ggx", "charlie"}, std::string("ggx")},
      {"size", PType::Int, 1, 16384, {}, 256.0},
      {"min_size", PType::Int, 1, 16384, {}, 16.0},
      {"schedule", PType::Name, 0, 0, {"linear", "filament", "sqrt"}, std::string("linear")},
      {"estimator", PType::Name, 0, 0, {"quadrature", "sampling"}, std::string("quadrature")},
      {"samples", PType::Int, 1, 1 << 24, {}, std::nullopt},
      {"max_error", PType::Number, 0, 1, {}, std::nullopt},
  };
  static const std::vector<PDef> irradiance = {
      {"sh_order", PType::Int, 3, 5, {}, 3.0},
      {"sh_window", PType::Name, 0, 0, {"none", "hanning", "lanczos"}, std::string("none")},
      {"cube_size", PType::Int, 0, 4096, {}, 0.0},
      {"source_size", PType::Int, 1, 16384, {}, 256.0},
  };
  switch (kind) {
    case TableKind::Ggx:
    case TableKind::GgxMultiscatter: return dfg;
    case TableKind::Charlie: return charlie;
    case TableKind::Fresnel: return fresnel;
    case TableKind::ThinFilm: return thin_film;
    case TableKind::Prefilter: return prefilter;
    case TableKind::Irradiance: return irradiance;
  }
  return dfg;
}

const char* const kTableKeys[] = {"kind", "output", "format", "pixel", "precision", "device", "environment",
                                  "requested_by", "materials"};

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

std::string expected_keys(TableKind kind) {
  std::vector<std::string> names(std::begin(kTableKeys), std::end(kTableKeys));
  for (const auto& d : schema(kind)) names.push_back(d.name);
  return join(names);
}

const PDef* find_def(TableKind kind, const std::string& name) {
  for (const auto& d : schema(kind))
    if (d.name == name) return &d;
  return nullptr;
}

Param* find_param(Params& params, const std::string& name) {
  for (auto& p : params)
    if (p.name == name) return &p;
  return nullptr;
}

std::string value_text(const ParamValue& v) {
  if (auto b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (auto d = std::get_if<double>(&v)) return num(*d);
  if (auto s = std::get_if<std::string>(&v)) return "'" + *s + "'";
  std::string s = "[";
  for (double d : std::get<std::vector<double>>(v)) s += (s.size() > 1 ? ", " : "") + num(d);
  return s + "]";
}

// Checks one parameter's type and range; the error names the field.
void check_param(const PDef& d, const ParamValue& v, const std::string& where) {
  auto fail = [&](const std::string& what) { throw Error(where + ": " + what + " (got " + value_text(v) + ")"); };
  auto in_range = [&](double x) { return std::isfinite(x) && x >= d.lo && x <= d.hi; };
  auto range = [&]() {
    if (d.lo == 0 && d.name.find("max_error") != std::string::npos) return std::string("positive, at most ") + num(d.hi);
    if (std::isinf(d.hi)) return "at least " + num(d.lo);
    return "in " + num(d.lo) + ".." + num(d.hi);
  };
  switch (d.type) {
    case PType::Int: {
      const double* x = std::get_if<double>(&v);
      if (!x || std::floor(*x) != *x) fail("must be an integer");
      if (!in_range(*x)) fail("must be an integer " + range());
      break;
    }
    case PType::Number: {
      const double* x = std::get_if<double>(&v);
      if (!x) fail("must be a number");
      if (!in_range(*x) || (d.lo == 0 && d.name == "max_error" && *x <= 0)) fail("must be a number " + range());
      break;
    }
    case PType::Name: {
      const std::string* s = std::get_if<std::string>(&v);
      if (!s) fail("must be a string");
      if (!d.choices.empty() && std::find(d.choices.begin(), d.choices.end(), *s) == d.choices.end())
        fail("must be one of " + join(d.choices, ", "));
      break;
    }
    case PType::Flag:
      if (!std::holds_alternative<bool>(v)) fail("must be true or false");
      break;
    case PType::Rgb: {
      if (const double* x = std::get_if<double>(&v)) {
        if (!in_range(*x)) fail("must be a number " + range());
      } else if (const auto* a = std::get_if<std::vector<double>>(&v)) {
        if (a->size() != 3) fail("must be a number or an array of 3 numbers (r, g, b)");
        for (double c : *a)
          if (!in_range(c)) fail("each channel must be " + range());
      } else {
        fail("must be a number or an array of 3 numbers (r, g, b)");
      }
      break;
    }
  }
}

// ---- Output names and formats ------------------------------------------------------------------

std::string name_number(double v) {
  std::string s = num(v, "%.6g");
  return s;
}

std::string default_extension(const TableRequest& t) {
  if (!t.format.empty()) {
    if (t.format == "dds-legacy") return "dds";
    if (t.format == "h") return "h";
    return t.format;
  }
  if (t.kind == TableKind::Prefilter) return "ktx2";
  if (t.kind == TableKind::Irradiance) return t.number("cube_size") > 0 ? "ktx2" : "json";
  if (t.kind == TableKind::Fresnel && t.flag("vs_exact")) return "csv";
  return "exr";
}

std::string ior_part(const ParamValue& v) {
  if (auto d = std::get_if<double>(&v)) return name_number(*d);
  std::string s;
  for (double x : std::get<std::vector<double>>(v)) s += (s.empty() ? "" : "_") + name_number(x);
  return s;
}

std::string default_output(const TableRequest& t) {
  std::string stem;
  const std::string size = num(t.number("size"), "%.0f");
  switch (t.kind) {
    case TableKind::Ggx:
    case TableKind::GgxMultiscatter:
    case TableKind::Charlie: {
      std::string kind = table_kind_name(t.kind);
      std::replace(kind.begin(), kind.end(), '-', '_');
      stem = "dfg_" + kind;
      if (t.kind == TableKind::Charlie && t.text("sheen_visibility") != "estevez-kulla")
        stem += "_" + t.text("sheen_visibility");
      stem += "_" + size;
      if (t.number("height") != t.number("size")) stem += "x" + num(t.number("height"), "%.0f");
      break;
    }
    case TableKind::Fresnel: {
      std::string model = t.text("model");
      std::replace(model.begin(), model.end(), '-', '_');
      stem = "fresnel_" + model;
      if (!t.text("material").empty()) stem += "_" + t.text("material");
      if (const ParamValue* v = t.find("ior")) {
        // schlick-ior's name already ends in "ior"
        stem += (model.size() >= 3 && model.compare(model.size() - 3, 3, "ior") == 0 ? "" : "_ior") + ior_part(*v);
      }
      if (const ParamValue* v = t.find("ior_outside")) stem += "_from" + ior_part(*v);
      if (const ParamValue* v = t.find("f0")) stem += "_f0_" + ior_part(*v);
      if (t.flag("vs_exact")) stem += "_vs_exact";
      break;
    }
    case TableKind::ThinFilm: {
      stem = "thin_film_ior" + name_number(t.number("film_ior"));
      if (const ParamValue* v = t.find("base_ior")) stem += "_base_ior" + ior_part(*v);
      if (const ParamValue* v = t.find("base_f0")) stem += "_base_f0_" + ior_part(*v);
      stem += "_" + name_number(t.number("thickness_min"));
      if (t.number("thickness_max") != t.number("thickness_min")) stem += "-" + name_number(t.number("thickness_max"));
      stem += "nm";
      break;
    }
    case TableKind::Prefilter:
      stem = "prefilter_" + t.text("distribution") + "_" + size;
      break;
    case TableKind::Irradiance:
      stem = "irradiance_sh" + num(t.number("sh_order"), "%.0f");
      if (t.number("cube_size") > 0) stem += "_cube" + num(t.number("cube_size"), "%.0f");
      break;
  }
  return stem + "." + default_extension(t);
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Checks the output path and format of a table; the error names the field.
void check_output(const TableRequest& t, const std::string& where) {
  const fs::path p(t.output);
  if (t.output.empty()) throw Error(where + ".output: must not be empty");
  if (p.is_absolute()) throw Error(where + ".output: '" + t.output + "' must be relative to the output folder");
  for (const auto& part : p)
    if (part == "..") throw Error(where + ".output: '" + t.output + "' must stay inside the output folder (no '..')");
  if (p.filename().empty() || p.filename() == "." || t.output.back() == '/')
    throw Error(where + ".output: '" + t.output + "' is not a file name");
  if (p.lexically_normal() == "manifest.json")
    throw Error(where + ".output: 'manifest.json' is the job's manifest");
  if (t.pixel != "f16" && t.pixel != "f32") throw Error(where + ".pixel: must be f16 or f32 (got '" + t.pixel + "')");
  const std::string ext = lower_extension(t.output);
  try {
    if (is_image_table(t.kind)) {
      const TableFormat f = t.format.empty() ? table_format_from_path(t.output) : table_format_from_name(t.format);
      if (t.kind == TableKind::Fresnel && t.flag("vs_exact") && f != TableFormat::Csv && f != TableFormat::CHeader)
        throw Error("vs_exact adds three error columns: write .csv or .h");
    } else if (t.kind == TableKind::Prefilter || (t.kind == TableKind::Irradiance && ext != ".json")) {
      if (ext != ".ktx2" && ext != ".ktx" && ext != ".dds")
        throw Error("'" + t.output + "': " + (t.kind == TableKind::Prefilter ? "a prefiltered chain" : "an irradiance cube") +
                    " is written to .ktx2, .ktx or .dds" + (t.kind == TableKind::Irradiance ? " (or SH to .json)" : ""));
      if (!t.format.empty() && t.format != ext.substr(1) && !(t.format == "dds-legacy" && ext == ".dds"))
        throw Error("format '" + t.format + "' does not match the extension of '" + t.output + "'");
      if (t.kind == TableKind::Irradiance && t.number("cube_size") <= 0)
        throw Error("an irradiance cube output needs cube_size > 0 (or write the SH to .json)");
    } else if (t.kind == TableKind::Irradiance) {
      if (!t.format.empty() && t.format != "json")
        throw Error("format '" + t.format + "' does not match the extension of '" + t.output + "'");
    }
  } catch (const Error& e) {
    throw Error(where + (t.format.empty() ? ".output: " : ".format: ") + e.what());
  }
}

std::string bake_key(const TableRequest& t, const Job& job) {
  std::string k = table_kind_name(t.kind);
  for (const auto& p : t.params) k += "|" + p.name + "=" + value_text(p.value);
  k += std::string("|precision=") + precision_name(t.precision);
  k += "|device=" + (t.device.empty() ? job.device : t.device);
  if (uses_environment(t.kind)) k += "|env=" + (t.environment.empty() ? job.environment : t.environment);
  return k;
}

// ---- JSON --------------------------------------------------------------------------------------

json param_json(const PDef* d, const ParamValue& v) {
  if (auto b = std::get_if<bool>(&v)) return *b;
  if (auto x = std::get_if<double>(&v)) {
    if (d && d->type == PType::Int) return static_cast<long long>(*x);
    return *x;
  }
  if (auto s = std::get_if<std::string>(&v)) return *s;
  return std::get<std::vector<double>>(v);
}

json requests_json(const std::vector<Request>& reqs) {
  json a = json::array();
  for (const auto& r : reqs) {
    json o;
    o["rule"] = r.rule;
    o["purpose"] = r.purpose;
    o["materials"] = r.materials;
    if (!r.note.empty()) o["note"] = r.note;
    a.push_back(o);
  }
  return a;
}

json params_json(TableKind kind, const Params& params) {
  json o = json::object();
  for (const auto& p : params) o[p.name] = param_json(find_def(kind, p.name), p.value);
  return o;
}

json table_json(const TableRequest& t, const Job& job) {
  json o;
  o["kind"] = table_kind_name(t.kind);
  const json params = params_json(t.kind, t.params);
  for (auto it = params.begin(); it != params.end(); ++it) o[it.key()] = *it;
  if (t.precision != job.precision) o["precision"] = precision_name(t.precision);
  if (!t.device.empty()) o["device"] = t.device;
  if (!t.environment.empty()) o["environment"] = t.environment;
  o["output"] = t.output;
  if (!t.format.empty()) o["format"] = t.format;
  if (t.pixel != "f16") o["pixel"] = t.pixel;
  if (!t.requested_by.empty()) {
    o["requested_by"] = requests_json(t.requested_by);
    o["materials"] = t.materials();
  }
  return o;
}

json job_json(const Job& job) {
  json o;
  o["brdfbake_job"] = 1;
  if (!job.output_dir.empty()) o["output_dir"] = job.output_dir;
  if (!job.scene.empty()) o["scene"] = job.scene;
  o["environment"] = job.environment;
  o["device"] = job.device;
  o["precision"] = precision_name(job.precision);
  json tables = json::array();
  for (const auto& t : job.tables) tables.push_back(table_json(t, job));
  o["tables"] = tables;
  if (!job.notes.empty()) o["notes"] = job.notes;
  if (!job.warnings.empty()) o["warnings"] = job.warnings;
  return o;
}

// Reads a JSON value into a ParamValue (numbers, strings, booleans, arrays of numbers).
ParamValue to_param(const json& v, const std::string& where) {
  if (v.is_boolean()) return v.get<bool>();
  if (v.is_number()) return v.get<double>();
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::vector<double> out;
    for (const auto& e : v) {
      if (!e.is_number()) throw Error(where + ": must be a number or an array of numbers (got " + v.dump() + ")");
      out.push_back(e.get<double>());
    }
    return out;
  }
  throw Error(where + ": must be a number, a string, a boolean or an array of numbers (got " + v.dump() + ")");
}

std::string get_string(const json& o, const std::string& key, const std::string& where) {
  const json& v = o.at(key);
  if (!v.is_string()) throw Error(where + "." + key + ": must be a string (got " + v.dump() + ")");
  return v.get<std::string>();
}

std::vector<std::string> get_strings(const json& o, const std::string& key, const std::string& where) {
  const json& v = o.at(key);
  std::vector<std::string> out;
  if (!v.is_array()) throw Error(where + "." + key + ": must be an array of strings");
  for (const auto& e : v) {
    if (!e.is_string()) throw Error(where + "." + key + ": must be an array of strings");
    out.push_back(e.get<std::string>());
  }
  return out;
}

TableRequest parse_table(const json& o, const std::string& where, bool* precision_given) {
  if (!o.is_object()) throw Error(where + ": must be an object");
  TableRequest t;
  t.precision = Precision::Fp32;
  if (!o.contains("kind")) throw Error(where + ".kind: missing (one of ggx, ggx-multiscatter, charlie, fresnel, "
                                       "thin-film, prefilter, irradiance)");
  try {
    t.kind = table_kind_from_name(get_string(o, "kind", where));
  } catch (const Error& e) {
    if (std::string(e.what()).rfind(where, 0) == 0) throw;
    throw Error(where + ".kind: " + e.what());
  }
  for (auto it = o.begin(); it != o.end(); ++it) {
    const std::string& key = it.key();
    const std::string field = where + "." + key;
    if (key == "kind") continue;
    if (key == "output") t.output = get_string(o, key, where);
    else if (key == "format") t.format = get_string(o, key, where);
    else if (key == "pixel") t.pixel = get_string(o, key, where);
    else if (key == "device") t.device = get_string(o, key, where);
    else if (key == "environment") t.environment = get_string(o, key, where);
    else if (key == "precision") {
      try {
        t.precision = precision_from_name(get_string(o, key, where));
      } catch (const Error& e) {
        if (std::string(e.what()).rfind(where, 0) == 0) throw;
        throw Error(field + ": " + e.what());
      }
      *precision_given = true;
    } else if (key == "materials") {
      get_strings(o, key, where);  // informative: derived from requested_by
    } else if (key == "requested_by") {
      if (!it->is_array()) throw Error(field + ": must be an array of {rule, purpose, materials, note}");
      for (size_t i = 0; i < it->size(); ++i) {
        const json& r = (*it)[i];
        const std::string rw = field + "[" + std::to_string(i) + "]";
        if (!r.is_object()) throw Error(rw + ": must be an object");
        Request q;
        for (auto f = r.begin(); f != r.end(); ++f) {
          if (f.key() == "rule") q.rule = get_string(r, "rule", rw);
          else if (f.key() == "purpose") q.purpose = get_string(r, "purpose", rw);
          else if (f.key() == "note") q.note = get_string(r, "note", rw);
          else if (f.key() == "materials") q.materials = get_strings(r, "materials", rw);
          else throw Error(rw + "." + f.key() + ": unknown field (expected rule, purpose, materials, note)");
        }
        t.requested_by.push_back(q);
      }
    } else if (find_def(t.kind, key)) {
      t.params.push_back({key, to_param(*it, field)});
    } else {
      throw Error(field + ": unknown field for kind '" + std::string(table_kind_name(t.kind)) + "' (expected " +
                  expected_keys(t.kind) + ")");
    }
  }
  return t;
}

// ---- Adapters: one per kind --------------------------------------------------------------------

// What a bake produced: one of a table, a cube chain or an irradiance result.
struct Baked {
  std::optional<Table> table;        // DFG, Fresnel, thin film
  std::optional<Table> table_extra;  // Fresnel vs_exact: the table with error columns
  std::optional<CubeLevels> cube;
  std::optional<IrradianceResult> irradiance;
  std::optional<double> error_bound;
  std::string error_bound_definition;
  Params resolved;                   // parameters the family resolved (e.g. DFG samples)
  Metadata details;
  std::string device_name;
};

Rgb rgb_of(const ParamValue& v) {
  if (auto d = std::get_if<double>(&v)) return {*d, *d, *d};
  const auto& a = std::get<std::vector<double>>(v);
  return {a[0], a[1], a[2]};
}

std::optional<double> parse_bound(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

// DFG tables (brdfbake/lut.hpp).
LutSpec dfg_spec(const TableRequest& t) {
  LutSpec s;
  s.kind = t.kind == TableKind::Ggx ? LutKind::Ggx : t.kind == TableKind::GgxMultiscatter ? LutKind::GgxMultiscatter
                                                                                           : LutKind::Charlie;
  s.width = static_cast<int>(t.number("size"));
  s.height = static_cast<int>(t.number("height", t.number("size")));
  s.samples = static_cast<int>(t.number("samples", 0));
  s.max_error = t.number("max_error", 0);
  s.estimator = estimator_from_name(t.text("estimator", "quadrature"));
  if (t.kind == TableKind::Charlie) s.sheen_visibility = sheen_visibility_from_name(t.text("sheen_visibility"));
  s.precision = t.precision;
  return s;
}
void check_dfg(const TableRequest& t) { resolve_lut_spec(dfg_spec(t)); }
Baked bake_dfg(const TableRequest& t, Device* device, const std::function<void(double, const std::string&)>& progress) {
  const LutSpec spec = dfg_spec(t);
  Baked b;
  auto p = [&](double f) { progress(f, ""); };
  b.table = device ? bake_lut(*device, spec, nullptr, p) : bake_lut_reference(spec, nullptr, p);
  b.error_bound = parse_bound(b.table->meta("error_bound"));
  b.error_bound_definition = b.table->meta("error_bound_definition");
  if (!b.table->meta("error_bound_measured_at").empty())
    b.details.push_back({"error_bound_measured_at", b.table->meta("error_bound_measured_at")});
  if (const auto s = parse_bound(b.table->meta("samples"))) b.resolved.push_back({"samples", *s});
  b.details.push_back({"channels", b.table->meta("channels")});
  return b;
}

// Fresnel tables (brdfbake/fresnel.hpp).
FresnelSpec fresnel_spec(const TableRequest& t) {
  FresnelSpec s;
  s.model = fresnel_model_from_name(t.text("model"));
  s.material = t.text("material");
  if (auto v = t.find("ior")) s.ior = rgb_of(*v);
  if (auto v = t.find("ior_outside")) s.ior_outside = std::get<double>(*v);
  if (auto v = t.find("f0")) s.f0 = rgb_of(*v);
  if (auto v = t.find("f90")) s.f90 = rgb_of(*v);
  if (auto v = t.find("n")) s.n = rgb_of(*v);
  if (auto v = t.find("k")) s.k = rgb_of(*v);
  s.size = static_cast<int>(t.number("size"));
  s.endpoints = t.flag("endpoints");
  s.precision = t.precision;
  return s;
}
void check_fresnel(const TableRequest& t) {
  if (!t.find("model")) throw Error("model: missing (e.g. dielectric, schlick-ior, conductor)");
  const FresnelSpec s = fresnel_spec(t);
  validate_fresnel_spec(s);
  if (t.flag("vs_exact")) exact_fresnel_spec(s);
}
Baked bake_fresnel_table(const TableRequest& t, Device* device) {
  const FresnelSpec spec = fresnel_spec(t);
  Baked b;
  b.table = device ? bake_fresnel(*device, spec) : bake_fresnel_reference(spec);
  const Table reference = bake_fresnel_reference(spec);
  b.error_bound = fresnel_error(*b.table, reference).max_abs;
  b.error_bound_definition = device ? "max |table - scalar double reference| over every cell and channel, measured "
                                      "when the table was baked"
                                    : "the scalar double reference itself";
  if (t.flag("vs_exact")) {
    b.table_extra = with_error_columns(*b.table, bake_fresnel_reference(exact_fresnel_spec(spec)));
    b.details.push_back({"error_vs_exact_max_abs", b.table_extra->meta("error_max_abs")});
    b.details.push_back({"error_vs_exact_mean_abs", b.table_extra->meta("error_mean_abs")});
  }
  return b;
}

// Thin-film tables (thin_film_adapter.hpp: absent from builds without the module).
void check_thin_film(const TableRequest& t) {
  const bool ior = t.find("base_ior") != nullptr, f0 = t.find("base_f0") != nullptr;
  if (ior == f0) throw Error("give exactly one of base_ior (a dielectric base) and base_f0 (a metal's F0)");
  if (t.number("thickness_max") < t.number("thickness_min"))
    throw Error("thickness_max: must be at least thickness_min (got " + num(t.number("thickness_max")) + " < " +
                num(t.number("thickness_min")) + ")");
  if (t.number("thickness_max") == t.number("thickness_min") && t.number("height") != 1)
    throw Error("height: must be 1 when thickness_min = thickness_max (one thickness)");
}
Baked bake_thin_film_table(const TableRequest& t, Device* device) {
  Baked b;
  detail::ThinFilmRequest r;
  r.film_ior = t.number("film_ior");
  r.outside_ior = t.number("outside_ior");
  if (auto v = t.find("base_ior")) r.base_ior = std::get<double>(*v);
  if (auto v = t.find("base_f0")) r.base_f0 = rgb_of(*v);
  r.thickness_min = t.number("thickness_min");
  r.thickness_max = t.number("thickness_max");
  r.width = static_cast<int>(t.number("size"));
  r.height = static_cast<int>(t.number("height"));
  r.precision = t.precision;
  detail::ThinFilmResult res = detail::bake_thin_film_adapter(device, r);
  b.table = std::move(res.table);
  b.error_bound = res.error_bound;
  b.error_bound_definition = res.error_bound_definition;
  return b;
}

// Prefiltered chains (brdfbake/environment.hpp).
PrefilterSpec prefilter_spec(const TableRequest& t) {
  PrefilterSpec s;
  s.distribution = env_distribution_from_name(t.text("distribution"));
  s.size = static_cast<int>(t.number("size"));
  s.min_size = static_cast<int>(t.number("min_size"));
  s.schedule = roughness_schedule_from_name(t.text("schedule"));
  s.estimator = env_estimator_from_name(t.text("estimator"));
  s.samples = static_cast<int>(t.number("samples", 0));
  s.max_error = t.number("max_error", 0);
  s.precision = t.precision;
  return s;
}
void check_prefilter(const TableRequest& t) {
  if (t.device == "reference") throw Error("device: 'reference' cannot prefilter; choose an OpenCL device");
  if (t.find("samples") && t.text("estimator") != "sampling")
    throw Error("samples: needs estimator 'sampling' (the quadrature takes max_error)");
  if (t.number("min_size") > t.number("size"))
    throw Error("min_size: must be at most size (got " + num(t.number("min_size")) + " > " + num(t.number("size")) + ")");
  resolve_prefilter_spec(prefilter_spec(t));
}
Baked bake_prefilter_chain(const TableRequest& t, Device& device, const EnvImage& env,
                           const std::function<void(double, const std::string&)>& progress) {
  Baked b;
  b.cube = prefilter_environment(device, env, prefilter_spec(t), nullptr, progress);
  if (t.number("max_error", 0) > 0) {
    b.error_bound = t.number("max_error");
    b.error_bound_definition = b.cube->meta("max_error");
  } else {
    b.error_bound_definition = "not measured when baked (the quadrature's accuracy against the reference is in "
                               "docs/BENCHMARKS.md; give max_error for a per-level measurement)";
  }
  b.details.push_back({"levels", b.cube->meta("levels")});
  b.details.push_back({"lod_from_roughness", b.cube->meta("lod_from_roughness")});
  return b;
}

// Irradiance (brdfbake/environment.hpp).
IrradianceSpec irradiance_spec(const TableRequest& t) {
  IrradianceSpec s;
  s.sh_order = static_cast<int>(t.number("sh_order"));
  s.window = sh_window_from_name(t.text("sh_window"));
  s.cube_size = static_cast<int>(t.number("cube_size"));
  s.source_size = static_cast<int>(t.number("source_size"));
  s.precision = t.precision;
  return s;
}
void check_irradiance(const TableRequest& t) {
  if (t.device == "reference") throw Error("device: 'reference' cannot compute irradiance; choose an OpenCL device");
  if (t.number("sh_order") != 3 && t.number("sh_order") != 5)
    throw Error("sh_order: must be 3 or 5 (got " + num(t.number("sh_order")) + ")");
  irradiance_spec(t);
}
Baked bake_irradiance_sh(const TableRequest& t, Device& device, const EnvImage& env,
                         const std::function<void(double, const std::string&)>& progress) {
  Baked b;
  b.irradiance = compute_irradiance(device, env, irradiance_spec(t), progress);
  b.error_bound_definition = "not measured when baked (SH projection of the source cube)";
  b.details.push_back({"sh_coefficients", std::to_string(b.irradiance->sh.order * b.irradiance->sh.order)});
  return b;
}

void check_family(const TableRequest& t) {
  switch (t.kind) {
    case TableKind::Ggx:
    case TableKind::GgxMultiscatter:
    case TableKind::Charlie: return check_dfg(t);
    case TableKind::Fresnel: return check_fresnel(t);
    case TableKind::ThinFilm: return check_thin_film(t);
    case TableKind::Prefilter: return check_prefilter(t);
    case TableKind::Irradiance: return check_irradiance(t);
  }
}

// ---- Writing -----------------------------------------------------------------------------------

void write_output(const Baked& b, const TableRequest& t, const std::string& path, const std::string& env_source) {
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) fs::create_directories(parent, ec);
  PixelType pixel = t.pixel == "f32" ? PixelType::F32 : PixelType::F16;
  if (b.table) {
    const Table& table = b.table_extra ? *b.table_extra : *b.table;
    const TableFormat f = t.format.empty() ? table_format_from_path(path) : table_format_from_name(t.format);
    TableWriteOptions o;
    o.pixel = pixel;
    write_table(table, path, f, o);
  } else if (b.cube) {
    CubeFormat f = cube_format_from_path(path);
    if (f == CubeFormat::Dds && t.format == "dds-legacy") f = CubeFormat::DdsLegacy;
    CubeWriteOptions o;
    o.pixel = pixel;
    write_cubemap(*b.cube, path, f, o);
  } else if (b.irradiance) {
    if (lower_extension(path) == ".json") {
      write_sh_json(b.irradiance->sh, {{"source", env_source}, {"source_size", num(t.number("source_size"), "%.0f")}},
                    path);
    } else {
      CubeFormat f = cube_format_from_path(path);
      if (f == CubeFormat::Dds && t.format == "dds-legacy") f = CubeFormat::DdsLegacy;
      CubeWriteOptions o;
      o.pixel = pixel;
      o.stem = "irradiance";
      write_cubemap(b.irradiance->cube, path, f, o);
    }
  }
}

// A temporary folder beside the output folder, removed unless committed.
class StagingDir {
 public:
  explicit StagingDir(const fs::path& target) : target_(target) {
    fs::path parent = target.parent_path();
    if (parent.empty()) parent = ".";
    std::error_code ec;
    if (!fs::exists(parent, ec)) {
      // Create the missing parents, remembering them so that a failure removes them again.
      std::vector<fs::path> missing;
      for (fs::path p = parent; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) missing.push_back(p);
      for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
        if (!fs::create_directory(*it, ec) && ec) io::throw_write_error(target.string(), ec.message());
        created_parents_.push_back(*it);
      }
    }
    if (fs::exists(target, ec) && !fs::is_directory(target, ec))
      io::throw_write_error(target.string(), "it exists and is not a folder");
    std::mt19937_64 g{std::random_device{}()};
    for (int attempt = 0; attempt < 8; ++attempt) {
      const fs::path candidate =
          parent / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" + num(double(g() % 1000000000ull), "%.0f"));
      if (fs::create_directory(candidate, ec)) {
        path_ = candidate;
        return;
      }
      if (ec) io::throw_write_error(target.string(), ec.message());
    }
    io::throw_write_error(target.string(), "could not create a temporary folder beside it");
  }
  ~StagingDir() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
    if (!committed_)
      for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it) fs::remove(*it, ec);
  }
  StagingDir(const StagingDir&) = delete;
  StagingDir& operator=(const StagingDir&) = delete;

  const fs::path& path() const { return path_; }

  // Moves the files into the target: the whole folder when the target does not exist yet, else file
  // by file, `last` (the manifest) after all the others.
  void commit(const std::vector<std::string>& files, const std::string& last) {
    std::error_code ec;
    if (!fs::exists(target_, ec)) {
      fs::rename(path_, target_, ec);
      if (ec) io::throw_write_error(target_.string(), ec.message());
      path_.clear();
      committed_ = true;
      return;
    }
    std::vector<std::string> order = files;
    order.push_back(last);
    for (const auto& f : order) {
      const fs::path to = target_ / f;
      if (!to.parent_path().empty()) fs::create_directories(to.parent_path(), ec);
      if (fs::is_directory(to, ec)) io::throw_write_error(to.string(), "a folder of that name is in the way");
    }
    for (const auto& f : order) {
      fs::rename(path_ / f, target_ / f, ec);
      if (ec) io::throw_write_error((target_ / f).string(), ec.message());
    }
    committed_ = true;
  }

 private:
  fs::path target_;
  fs::path path_;
  std::vector<fs::path> created_parents_;
  bool committed_ = false;
};

}  // namespace

// ---- Public: kinds -----------------------------------------------------------------------------

TableKind table_kind_from_name(const std::string& name) {
  for (const auto& [n, k] : kKindNames)
    if (name == n) return k;
  std::vector<std::string> names;
  for (const auto& [n, k] : kKindNames) names.push_back(n);
  throw Error("unknown table kind '" + name + "' (known: " + join(names) + ")");
}

const char* table_kind_name(TableKind kind) {
  for (const auto& [n, k] : kKindNames)
    if (k == kind) return n;
  return "?";
}

const std::vector<TableKind>& table_kinds() {
  static const std::vector<TableKind> kinds = [] {
    std::vector<TableKind> v;
    for (const auto& [n, k] : kKindNames) v.push_back(k);
    return v;
  }();
  return kinds;
}

bool table_kind_available(TableKind kind, std::string* why) {
  // Developer and test switch: kinds listed here (comma separated) are treated as missing.
  if (const char* off = std::getenv("BRDFBAKE_UNAVAILABLE_KINDS")) {
    const std::string list = std::string(",") + off + ",";
    if (list.find(std::string(",") + table_kind_name(kind) + ",") != std::string::npos) {
      if (why) *why = std::string("disabled by BRDFBAKE_UNAVAILABLE_KINDS");
      return false;
    }
  }
  if (kind == TableKind::ThinFilm && !detail::thin_film_available()) {
    if (why)
      *why = "the thin-film interference Fresnel module (KHR_materials_iridescence; Belcour & Barla 2017) is not in "
             "this build";
    return false;
  }
  return true;
}

// ---- Public: requests --------------------------------------------------------------------------

const ParamValue* TableRequest::find(const std::string& name) const {
  for (const auto& p : params)
    if (p.name == name) return &p.value;
  return nullptr;
}

double TableRequest::number(const std::string& name, double fallback) const {
  const ParamValue* v = find(name);
  if (!v) return fallback;
  if (auto d = std::get_if<double>(v)) return *d;
  return fallback;
}

std::string TableRequest::text(const std::string& name, const std::string& fallback) const {
  const ParamValue* v = find(name);
  if (!v) return fallback;
  if (auto s = std::get_if<std::string>(v)) return *s;
  return fallback;
}

bool TableRequest::flag(const std::string& name, bool fallback) const {
  const ParamValue* v = find(name);
  if (!v) return fallback;
  if (auto b = std::get_if<bool>(v)) return *b;
  return fallback;
}

std::vector<std::string> TableRequest::materials() const {
  std::vector<std::string> out;
  for (const auto& r : requested_by)
    for (const auto& m : r.materials)
      if (std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
  return out;
}

// ---- Public: validation, parsing, JSON ---------------------------------------------------------

void validate_job(Job& job) {
  const std::string origin = job.source.empty() ? std::string("job") : job.source;
  if (job.environment.empty()) throw Error(origin + ": environment: must not be empty");
  for (size_t i = 0; i < job.tables.size(); ++i) {
    TableRequest& t = job.tables[i];
    const std::string where = origin + ": tables[" + std::to_string(i) + "]";
    // Types and ranges, then defaults, in the kind's canonical order.
    Params ordered;
    for (const auto& d : schema(t.kind)) {
      Param* given = find_param(t.params, d.name);
      if (given) {
        check_param(d, given->value, where + "." + d.name);
        ordered.push_back(*given);
      } else if (d.fallback) {
        ordered.push_back({d.name, *d.fallback});
      }
    }
    for (const auto& p : t.params)
      if (!find_def(t.kind, p.name))
        throw Error(where + "." + p.name + ": unknown field for kind '" + table_kind_name(t.kind) + "' (expected " +
                    expected_keys(t.kind) + ")");
    t.params = ordered;
    auto set_default = [&](const std::string& name, const ParamValue& v) {
      if (find_param(t.params, name)) return;
      // keep the canonical order: insert after the parameter that precedes it in the schema
      const auto& s = schema(t.kind);
      size_t at = 0;
      for (const auto& d : s) {
        if (d.name == name) break;
        if (find_param(t.params, d.name)) ++at;
      }
      t.params.insert(t.params.begin() + static_cast<long>(at), {name, v});
    };
    if (is_dfg(t.kind)) set_default("height", t.number("size"));
    if (t.kind == TableKind::ThinFilm)
      set_default("height", t.number("thickness_max") == t.number("thickness_min") ? 1.0 : t.number("size"));
    if (t.find("samples") && t.find("max_error"))
      throw Error(where + ".max_error: give samples or max_error, not both");
    try {
      check_family(t);
    } catch (const Error& e) {
      throw Error(where + " (" + table_kind_name(t.kind) + "): " + e.what());
    }
    if (t.output.empty()) t.output = default_output(t);
    check_output(t, where);
  }
  // Identical requests merge; two different tables may not share an output.
  std::vector<TableRequest> merged;
  std::map<std::string, size_t> by_output;
  for (size_t i = 0; i < job.tables.size(); ++i) {
    TableRequest& t = job.tables[i];
    const std::string out = fs::path(t.output).lexically_normal().string();
    auto it = by_output.find(out);
    if (it == by_output.end()) {
      by_output[out] = merged.size();
      merged.push_back(t);
      continue;
    }
    TableRequest& first = merged[it->second];
    if (bake_key(first, job) != bake_key(t, job) || first.format != t.format || first.pixel != t.pixel) {
      size_t first_index = 0;
      for (size_t k = 0; k < i; ++k)
        if (fs::path(job.tables[k].output).lexically_normal().string() == out) {
          first_index = k;
          break;
        }
      throw Error(origin + ": tables[" + std::to_string(i) + "].output: '" + t.output + "' is also the output of tables[" +
                  std::to_string(first_index) + "], a different table");
    }
    for (const auto& r : t.requested_by) first.requested_by.push_back(r);
  }
  job.tables = std::move(merged);
}

Job parse_job(const std::string& text, const std::string& origin) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    if (auto p = what.find("parse error"); p != std::string::npos) what = what.substr(p);
    throw Error(origin + ": malformed JSON: " + what);
  }
  if (!root.is_object()) throw Error(origin + ": a job is a JSON object with a \"tables\" array");
  Job job;
  job.source = origin;
  const std::string where = origin;
  for (auto it = root.begin(); it != root.end(); ++it) {
    const std::string& key = it.key();
    const std::string field = origin + ": " + key;
    if (key == "brdfbake_job") {
      if (!it->is_number_integer() || it->get<long long>() != 1)
        throw Error(field + ": must be 1 (the job format's version; got " + it->dump() + ")");
    } else if (key == "output_dir") {
      if (!it->is_string()) throw Error(field + ": must be a string");
      job.output_dir = it->get<std::string>();
    } else if (key == "environment") {
      if (!it->is_string()) throw Error(field + ": must be a string (FILE or builtin:NAME)");
      job.environment = it->get<std::string>();
    } else if (key == "device") {
      if (!it->is_string()) throw Error(field + ": must be a string");
      job.device = it->get<std::string>();
    } else if (key == "precision") {
      if (!it->is_string()) throw Error(field + ": must be a string (fp32 or fp64)");
      try {
        job.precision = precision_from_name(it->get<std::string>());
      } catch (const Error& e) {
        throw Error(field + ": " + e.what());
      }
    } else if (key == "scene") {
      if (!it->is_string()) throw Error(field + ": must be a string");
      job.scene = it->get<std::string>();
    } else if (key == "notes" || key == "warnings") {
      if (!it->is_array()) throw Error(field + ": must be an array of strings");
      for (const auto& e : *it) {
        if (!e.is_string()) throw Error(field + ": must be an array of strings");
        (key == "notes" ? job.notes : job.warnings).push_back(e.get<std::string>());
      }
    } else if (key == "plan") {
      if (!it->is_object()) throw Error(field + ": must be an object");  // informative (bake --dry-run --json)
    } else if (key == "tables") {
      if (!it->is_array()) throw Error(field + ": must be an array of tables");
    } else {
      throw Error(field + ": unknown field (expected brdfbake_job, output_dir, environment, device, precision, "
                          "tables, scene, notes, warnings, plan)");
    }
  }
  if (!root.contains("tables")) throw Error(origin + ": tables: missing (the list of tables to bake)");
  const json& tables = root["tables"];
  for (size_t i = 0; i < tables.size(); ++i) {
    bool precision_given = false;
    TableRequest t = parse_table(tables[i], where + ": tables[" + std::to_string(i) + "]", &precision_given);
    if (!precision_given) t.precision = job.precision;
    job.tables.push_back(std::move(t));
  }
  validate_job(job);
  return job;
}

Job read_job(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::error_code ec;
    throw Error("cannot read job '" + path + "': " + (fs::exists(path, ec) ? "permission denied" : "no such file"));
  }
  std::ostringstream s;
  s << in.rdbuf();
  return parse_job(s.str(), path);
}

std::string job_to_json(const Job& job) { return job_json(job).dump(2) + "\n"; }

std::string plan_to_json(const Plan& plan) {
  json o = job_json(plan.job);
  json p;
  const PlanOptions& opt = plan.options;
  p["energy_compensation"] = opt.energy_compensation;
  p["rules_fired"] = plan.rules_fired;
  json mats = json::array();
  for (const auto& m : plan.materials) {
    json e;
    e["material"] = m.label;
    e["reached_by"] = m.reached_by;
    e["counted"] = m.counted;
    e["rules"] = m.rules;
    if (!m.notes.empty()) e["notes"] = m.notes;
    mats.push_back(e);
  }
  p["materials"] = mats;
  o["plan"] = p;
  return o.dump(2) + "\n";
}

std::string manifest_to_json(const Manifest& m) {
  json o;
  o["generator"] = std::string("brdfbake ") + kVersion;
  o["job"] = m.job_source;
  if (!m.scene.empty()) o["scene"] = m.scene;
  o["bakes"] = m.bakes;
  o["seconds"] = m.seconds;
  json files = json::array();
  for (const auto& f : m.files) {
    json e;
    e["path"] = f.path;
    e["kind"] = table_kind_name(f.kind);
    e["parameters"] = params_json(f.kind, f.params);
    e["precision"] = precision_name(f.precision);
    e["device"] = f.device;
    if (!f.environment.empty()) e["environment"] = f.environment;
    if (f.error_bound) e["error_bound"] = *f.error_bound;
    else e["error_bound"] = nullptr;
    e["error_bound_definition"] = f.error_bound_definition;
    for (const auto& [k, v] : f.details) e[k] = v;
    e["materials"] = f.materials;
    e["requested_by"] = requests_json(f.requested_by);
    e["bytes"] = f.bytes;
    e["bake"] = f.bake;
    e["seconds"] = f.seconds;
    files.push_back(e);
  }
  o["files"] = files;
  if (!m.notes.empty()) o["notes"] = m.notes;
  if (!m.warnings.empty()) o["warnings"] = m.warnings;
  return o.dump(2) + "\n";
}

// ---- Public: running ---------------------------------------------------------------------------

Manifest run_job(const Job& in, const JobProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  Job job = in;
  validate_job(job);
  const std::string origin = job.source.empty() ? std::string("job") : job.source;
  if (job.output_dir.empty()) throw Error(origin + ": output_dir: missing (the folder to write into)");

  // Every kind must be bakeable before anything starts.
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
  if (!missing.empty())
    throw NotAvailableError(origin + ": not available in this build: " + join(missing, "; ") +
                            "; nothing was written");

  // Group identical tables: each group is baked once.
  std::vector<std::vector<size_t>> groups;
  {
    std::map<std::string, size_t> by_key;
    for (size_t i = 0; i < job.tables.size(); ++i) {
      const std::string k = bake_key(job.tables[i], job);
      auto it = by_key.find(k);
      if (it == by_key.end()) {
        by_key[k] = groups.size();
        groups.push_back({i});
      } else {
        groups[it->second].push_back(i);
      }
    }
  }

  std::string target = job.output_dir;
  while (target.size() > 1 && target.back() == '/') target.pop_back();  // "out/" is the folder "out"
  StagingDir staging{fs::path(target)};

  // Environments first (a bad file fails before any device work), each loaded once.
  std::map<std::string, EnvImage> environments;
  for (const auto& t : job.tables)
    if (uses_environment(t.kind)) {
      const std::string e = t.environment.empty() ? job.environment : t.environment;
      if (!environments.count(e)) environments.emplace(e, load_environment(e));
    }

  std::map<std::string, Device> devices;
  auto device_for = [&](const TableRequest& t) -> Device* {
    const std::string sel = t.device.empty() ? job.device : t.device;
    if (sel == "reference") return nullptr;
    auto it = devices.find(sel);
    if (it == devices.end()) it = devices.emplace(sel, Device::open(sel)).first;
    return &it->second;
  };

  Manifest manifest;
  manifest.output_dir = job.output_dir;
  manifest.job_source = origin;
  manifest.scene = job.scene;
  manifest.notes = job.notes;
  manifest.warnings = job.warnings;
  manifest.bakes = static_cast<int>(groups.size());
  std::vector<std::string> written;

  for (size_t g = 0; g < groups.size(); ++g) {
    const TableRequest& t = job.tables[groups[g].front()];
    std::string what = table_kind_name(t.kind);
    if (t.kind == TableKind::Prefilter) what += " " + t.text("distribution");
    if (t.kind == TableKind::Fresnel) what += " " + t.text("model");
    if (t.find("size")) what += " " + num(t.number("size"), "%.0f");
    auto report = [&](double fraction, const std::string& step) {
      if (progress) progress({int(g), int(groups.size()), step.empty() ? what : what + ": " + step, fraction});
    };
    report(0.0, "");
    const auto b0 = std::chrono::steady_clock::now();
    Device* device = device_for(t);
    const std::string env = t.environment.empty() ? job.environment : t.environment;
    Baked b;
    switch (t.kind) {
      case TableKind::Ggx:
      case TableKind::GgxMultiscatter:
      case TableKind::Charlie: b = bake_dfg(t, device, report); break;
      case TableKind::Fresnel: b = bake_fresnel_table(t, device); break;
      case TableKind::ThinFilm: b = bake_thin_film_table(t, device); break;
      case TableKind::Prefilter: b = bake_prefilter_chain(t, *device, environments.at(env), report); break;
      case TableKind::Irradiance: b = bake_irradiance_sh(t, *device, environments.at(env), report); break;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - b0).count();
    report(1.0, "");
    for (size_t k = 0; k < groups[g].size(); ++k) {
      const TableRequest& o = job.tables[groups[g][k]];
      const std::string rel = fs::path(o.output).lexically_normal().string();
      const fs::path path = staging.path() / rel;
      write_output(b, o, path.string(), env);
      written.push_back(rel);
      ManifestFile f;
      f.path = rel;
      f.kind = o.kind;
      f.params = o.params;
      for (const auto& r : b.resolved) {
        if (Param* p = find_param(f.params, r.name)) p->value = r.value;
        else f.params.push_back(r);
      }
      f.precision = o.precision;
      f.device = device ? device->info().name : std::string("reference");
      if (uses_environment(o.kind)) f.environment = env;
      f.error_bound = b.error_bound;
      f.error_bound_definition = b.error_bound_definition;
      f.details = b.details;
      f.requested_by = o.requested_by;
      f.materials = o.materials();
      std::error_code ec;
      f.bytes = static_cast<std::uint64_t>(fs::file_size(path, ec));
      f.seconds = k == 0 ? seconds : 0.0;
      f.bake = static_cast<int>(g);
      manifest.files.push_back(std::move(f));
    }
  }

  manifest.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  io::write_file_atomically((staging.path() / "manifest.json").string(), manifest_to_json(manifest));
  staging.commit(written, "manifest.json");
  return manifest;
}

}  // namespace brdfbake
