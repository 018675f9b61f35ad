// The family registry: kinds and their names, requests, schema-driven validation, and the two calls
// every front end bakes and writes through. Nothing here knows a family's parameters: those live in
// each family's descriptor (host/src/families/<family>.cpp).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "families/family.hpp"
#include "io/atomic_file.hpp"

namespace brdfbake {

namespace detail {

namespace fs = std::filesystem;

const std::vector<const Family*>& families() {
  static const std::vector<const Family*> all = {&dfg_lut_family(),    &fresnel_family(),    &thin_film_family(),
                                                 &prefilter_family(),  &irradiance_family(), &eval_family(),
                                                 &tabulate_family()};
  return all;
}

const Family& family_of(TableKind kind) {
  for (const Family* f : families())
    for (TableKind k : f->kinds())
      if (k == kind) return *f;
  throw Error("no family bakes table kind " + std::to_string(static_cast<int>(kind)));
}

std::string fmt_number(double v, const char* f) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string output_extension(const TableRequest& t) {
  if (!t.format.empty()) {
    if (t.format == "dds-legacy") return ".dds";
    return "." + t.format;
  }
  return lower_extension(t.output);
}

TableFormat table_output_format(const TableRequest& t) {
  return t.format.empty() ? table_format_from_path(t.output) : table_format_from_name(t.format);
}

PixelType pixel_of(const TableRequest& t) { return t.pixel == "f32" ? PixelType::F32 : PixelType::F16; }

Rgb rgb_of(const ParamValue& v) {
  if (auto d = std::get_if<double>(&v)) return {*d, *d, *d};
  const auto& a = std::get<std::vector<double>>(v);
  return {a[0], a[1], a[2]};
}

std::string name_part(const ParamValue& v) {
  if (auto d = std::get_if<double>(&v)) return fmt_number(*d, "%.6g");
  std::string s;
  for (double x : std::get<std::vector<double>>(v)) s += (s.empty() ? "" : "_") + fmt_number(x, "%.6g");
  return s;
}

std::uint64_t grid_bytes(double cells, double channels) {
  return static_cast<std::uint64_t>(cells * channels * 4 * 3 + cells * 16) + (std::uint64_t(1) << 20);
}

OutputFormats table_formats() {
  return {{".exr", ".png", ".hdr", ".ktx2", ".csv", ".h"}, "a table format (.exr .png .hdr .ktx2 .csv .h)"};
}

void write_table_result(const Table& table, const TableRequest& t, const std::string& path) {
  TableWriteOptions o;
  o.pixel = pixel_of(t);
  o.symbol = t.text("symbol");
  write_table(table, path, table_output_format(t), o);
}

void Family::check_output(const TableRequest& t, const FieldName&) const {
  const OutputFormats f = formats(t);
  const std::string ext = output_extension(t);
  if (std::find(f.extensions.begin(), f.extensions.end(), ext) != f.extensions.end()) return;
  if (!t.format.empty())
    throw FieldError("format", "'" + t.format + "' is not a format of " + table_kind_name(t.kind) + " (expected " +
                                   f.description + ")");
  throw FieldError("output", "unknown output format " + (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                                 " of '" + t.output + "' (" + table_kind_name(t.kind) + " writes " + f.description + ")");
}

}  // namespace detail

using detail::Family;
using detail::family_of;

namespace {

const std::pair<const char*, TableKind> kKindNames[] = {
    {"ggx", TableKind::Ggx},           {"ggx-multiscatter", TableKind::GgxMultiscatter},
    {"charlie", TableKind::Charlie},   {"fresnel", TableKind::Fresnel},
    {"thin-film", TableKind::ThinFilm}, {"prefilter", TableKind::Prefilter},
    {"irradiance", TableKind::Irradiance}, {"eval", TableKind::Eval},
    {"tabulate", TableKind::Tabulate}};

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

// The spelling of the common fields on the command line.
std::string common_cli(const std::string& field) {
  if (field == "output") return "-o";
  if (field == "environment") return "--env";
  return "--" + field;
}

Param* find_param(Params& params, const std::string& name) {
  for (auto& p : params)
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace

// ---- Kinds ---------------------------------------------------------------------------------------

TableKind table_kind_from_name(const std::string& name) {
  for (const auto& [n, k] : kKindNames)
    if (name == n) return k;
  std::vector<std::string> names;
  for (const auto& [n, k] : kKindNames) names.push_back(n);
  throw Error("unknown table kind '" + name.substr(0, 60) + "' (known: " + join(names) + ")");
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

std::string table_kind_command(TableKind kind) { return family_of(kind).command(); }

std::string table_kind_summary(TableKind kind) { return family_of(kind).summary(kind); }

bool table_kind_uses_environment(TableKind kind) { return family_of(kind).uses_environment(); }

bool table_kind_available(TableKind kind, std::string* why) {
  // Developer and test switch: kinds listed here (comma separated) are treated as missing.
  if (const char* off = std::getenv("BRDFBAKE_UNAVAILABLE_KINDS")) {
    const std::string list = std::string(",") + off + ",";
    if (list.find(std::string(",") + table_kind_name(kind) + ",") != std::string::npos) {
      if (why) *why = "disabled by BRDFBAKE_UNAVAILABLE_KINDS";
      return false;
    }
  }
  return true;
}

// ---- Requests ------------------------------------------------------------------------------------

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

std::vector<double> TableRequest::numbers(const std::string& name) const {
  const ParamValue* v = find(name);
  if (!v) return {};
  if (auto d = std::get_if<double>(v)) return {*d};
  if (auto a = std::get_if<std::vector<double>>(v)) return *a;
  return {};
}

void TableRequest::set(const std::string& name, ParamValue value) {
  if (Param* p = find_param(params, name)) {
    p->value = std::move(value);
    return;
  }
  // Keep the schema's order: insert after the parameters that precede it there.
  const auto& schema = table_schema(kind);
  size_t at = 0;
  for (const auto& d : schema) {
    if (d.name == name) break;
    if (find(d.name)) ++at;
  }
  params.insert(params.begin() + static_cast<long>(std::min(at, params.size())), {name, std::move(value)});
}

std::vector<std::string> TableRequest::materials() const {
  std::vector<std::string> out;
  for (const auto& r : requested_by)
    for (const auto& m : r.materials)
      if (std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
  return out;
}

// ---- Schemas and validation ----------------------------------------------------------------------

const std::vector<ParamDef>& table_schema(TableKind kind) { return family_of(kind).schema(kind); }

const std::vector<std::string>& table_common_fields() {
  static const std::vector<std::string> fields = {"kind",        "output", "format",       "pixel",    "precision",
                                                  "device",      "environment", "requested_by", "materials"};
  return fields;
}

std::string FieldNaming::field(TableKind kind, const std::string& name) const {
  if (cli) {
    if (const ParamDef* d = find_param_def(table_schema(kind), name)) return "--" + d->cli_name();
    return common_cli(name);
  }
  return prefix.empty() ? name : prefix + "." + name;
}

void validate_table(TableRequest& t, const FieldNaming& naming) {
  const Family& family = family_of(t.kind);
  const std::vector<ParamDef>& schema = family.schema(t.kind);
  auto field = [&](const std::string& name) { return naming.field(t.kind, name); };
  for (const auto& p : t.params)
    if (!find_param_def(schema, p.name)) {
      std::vector<std::string> names = table_common_fields();
      for (const auto& d : schema) names.push_back(d.name);
      throw Error(field(p.name) + ": unknown field for kind '" + table_kind_name(t.kind) + "' (expected " +
                  join(names) + ")");
    }
  // Types and ranges, then defaults, in the schema's order.
  Params ordered;
  for (const auto& d : schema) {
    if (Param* given = find_param(t.params, d.name)) {
      check_param(d, given->value, field(d.name));
      ordered.push_back(*given);
    } else if (d.fallback) {
      ordered.push_back({d.name, *d.fallback});
    } else if (d.required) {
      throw Error(field(d.name) + ": missing (" + d.help + ")");
    }
  }
  t.params = std::move(ordered);
  if (t.pixel.empty()) t.pixel = family.default_pixel();
  if (t.pixel != "f16" && t.pixel != "f32")
    throw Error(field("pixel") + ": must be f16 or f32 (got '" + t.pixel.substr(0, 60) + "')");
  const detail::FieldName name = [&](const std::string& f) { return naming.cli ? field(f) : f; };
  try {
    family.check(t, name);
    if (t.output.empty()) t.output = family.default_output(t);
    family.check_output(t, name);
  } catch (const detail::FieldError& e) {
    if (!e.field().empty()) throw Error(field(e.field()) + ": " + e.what());
    if (naming.cli) throw Error(e.what());
    throw Error(naming.prefix + (naming.prefix.empty() ? "" : " ") + "(" + table_kind_name(t.kind) + "): " + e.what());
  }
}

std::string default_table_output(const TableRequest& t) { return family_of(t.kind).default_output(t); }

std::uint64_t estimate_table_bytes(const TableRequest& t) { return family_of(t.kind).estimated_bytes(t); }

std::string table_bake_key(const TableRequest& t) {
  std::string k = table_kind_name(t.kind);
  const auto& schema = table_schema(t.kind);
  for (const auto& p : t.params) {
    const ParamDef* d = find_param_def(schema, p.name);
    if (d && d->output_only) continue;
    k += "|" + p.name + "=" + param_value_text(p.value);
  }
  k += std::string("|precision=") + precision_name(t.precision);
  k += "|device=" + t.device;
  if (table_kind_uses_environment(t.kind)) k += "|env=" + t.environment;
  return k;
}

// ---- Baking and writing --------------------------------------------------------------------------

BakeResult bake_table(const TableRequest& t, Backend& backend, const BakeInputs& inputs, const BakeProgress& progress) {
  const Family& family = family_of(t.kind);
  if (family.uses_environment() && !inputs.environment)
    throw Error(std::string(table_kind_name(t.kind)) + " needs an environment");
  const auto t0 = std::chrono::steady_clock::now();
  const BakeProgress report = progress ? progress : [](double, const std::string&) {};
  BakeResult r = family.bake(t, backend, inputs, report);
  r.kind = t.kind;
  r.device = backend.name();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Every parameter as baked: the request's, with what the family resolved (e.g. DFG samples).
  Params all = t.params;
  for (auto& p : r.parameters) {
    auto it = std::find_if(all.begin(), all.end(), [&](const Param& q) { return q.name == p.name; });
    if (it != all.end()) it->value = p.value;
    else all.push_back(p);
  }
  r.parameters = std::move(all);
  return r;
}

void write_result(const BakeResult& r, const TableRequest& t, const std::string& path) {
  io::ParentFolders parents(path);
  family_of(t.kind).write(r, t, path);
  parents.keep();
}

}  // namespace brdfbake
