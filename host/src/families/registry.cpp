// The family registry: kinds and their names, requests, schema-driven validation, and the two calls
// every front end bakes and writes through. Nothing here knows a family's parameters: those live in
// each family's descriptor (host/src/families/<family>.cpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <thread>

#include "brdfbake/cancel.hpp"
#include "families/family.hpp"
#include "io/atomic_file.hpp"
#include "io/storage.hpp"
#include "text.hpp"

namespace brdfbake {

namespace detail {

namespace fs = std::filesystem;

// The families, each defined in its folder (host/src/families/<family>/): adding one adds a line
// here (docs/ARCHITECTURE.md, "How to add a table family").
const Family& dfg_lut_family();
const Family& fresnel_family();
const Family& thin_film_family();
const Family& prefilter_family();
const Family& irradiance_family();
const Family& eval_family();
const Family& tabulate_family();
const Family& preview_family();

const std::vector<const Family*>& families() {
  static const std::vector<const Family*> all = {&dfg_lut_family(),   &fresnel_family(),    &thin_film_family(),
                                                 &prefilter_family(), &irradiance_family(), &eval_family(),
                                                 &tabulate_family(),  &preview_family()};
  return all;
}

const Family& family_of(TableKind kind) {
  for (const Family* f : families())
    for (TableKind k : f->kinds())
      if (k == kind) return *f;
  throw Error("no family bakes table kind " + std::to_string(static_cast<int>(kind)));
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

std::vector<double> probe_coordinates(int n) {
  // The lines between texel centres, i / n, and within half a texel of each edge (where clamp to
  // edge holds the outermost texel and the tables change fastest) points that close in on it
  // geometrically: 0.5 / n * 2^-k.
  std::vector<double> u;
  constexpr int kEdgePoints = 6;
  u.push_back(0.0);
  for (int k = kEdgePoints; k >= 1; --k) u.push_back(0.5 / n * std::ldexp(1.0, -k));
  for (int i = 1; i < n; ++i) u.push_back(static_cast<double>(i) / n);
  for (int k = 1; k <= kEdgePoints; ++k) u.push_back(1.0 - 0.5 / n * std::ldexp(1.0, -k));
  u.push_back(1.0);
  return u;
}

LookupError bilinear_lookup_error(const Table& t, const std::vector<double>& us, const std::vector<double>& vs,
                                  const Table& probe) {
  const int channels = t.channel_count();
  // texel coordinate of a lookup: (u * n - 0.5), clamped to the first and last centres
  auto split = [](double uv, int n, int* i0, double* f) {
    const double x = std::clamp(uv * n - 0.5, 0.0, double(n - 1));
    *i0 = std::min(static_cast<int>(x), std::max(n - 2, 0));
    *f = n > 1 ? x - *i0 : 0.0;
  };
  // outside the outermost centres (within half a texel of an edge) clamp to edge holds the value
  auto on_edge = [](double uv, int n) { return uv < 0.5 / n || uv > 1.0 - 0.5 / n; };
  LookupError e;
  for (size_t b = 0; b < vs.size(); ++b) {
    int j0 = 0;
    double fy = 0.0;
    split(vs[b], t.height, &j0, &fy);
    const int j1 = std::min(j0 + 1, t.height - 1);
    for (size_t a = 0; a < us.size(); ++a) {
      int i0 = 0;
      double fx = 0.0;
      split(us[a], t.width, &i0, &fx);
      const int i1 = std::min(i0 + 1, t.width - 1);
      const bool edge = on_edge(us[a], t.width) || (t.height > 1 && on_edge(vs[b], t.height));
      for (int c = 0; c < channels; ++c) {
        const double lookup = (1 - fy) * ((1 - fx) * double(t.at(i0, j0, c)) + fx * double(t.at(i1, j0, c))) +
                              fy * ((1 - fx) * double(t.at(i0, j1, c)) + fx * double(t.at(i1, j1, c)));
        const double truth = double(probe.at(static_cast<int>(a), static_cast<int>(b), c));
        const double d = std::fabs(lookup - truth) / std::max(1.0, std::fabs(truth));
        (edge ? e.edge : e.interior) = std::max(edge ? e.edge : e.interior, d);
      }
    }
  }
  return e;
}

std::uint64_t grid_bytes(double cells, double channels) {
  return static_cast<std::uint64_t>(cells * channels * 4 * 3 + cells * 16) + (std::uint64_t(1) << 20);
}

const EnvImage& headroom_environment(const EnvImage& in, EnvImage& storage, double* scale) {
  *scale = 1.0;
  float largest = 0.0f;
  for (float v : in.rgb) largest = std::max(largest, std::fabs(v));
  if (!(double(largest) > kRadianceHeadroom)) return in;
  int e = 0;
  std::frexp(double(largest) / kRadianceHeadroom, &e);  // largest / 2^32 < 2^e
  storage = in;
  const float down = static_cast<float>(std::ldexp(1.0, -e));
  for (float& v : storage.rgb) v *= down;
  *scale = std::ldexp(1.0, e);
  return storage;
}

std::string sanitize_note(const EnvImage& env) {
  if (!env.sanitize.replaced) return "";
  return std::to_string(env.sanitize.nan) + " NaN, " + std::to_string(env.sanitize.infinite) + " infinite and " +
         std::to_string(env.sanitize.negative) + " negative values replaced (--sanitize)";
}

void Family::check_output(const TableRequest& t, const FieldName&) const {
  const OutputFormats f = formats(t);
  const std::string ext = output_extension(t);
  if (std::find(f.extensions.begin(), f.extensions.end(), ext) != f.extensions.end()) return;
  if (!t.format.empty())
    throw FieldError("format", "'" + t.format + "' is not a format of " + table_kind_name(t.kind) + " (expected " +
                                   f.description + ")");
  throw FieldError("output", "unknown output format " +
                                 (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") + " of '" + t.output +
                                 "' (" + table_kind_name(t.kind) + " writes " + f.description + ")");
}

}  // namespace detail

using detail::Family;
using detail::family_of;

namespace {

// Every kind with its name, in the order of families() and of each family's kinds().
struct KindName {
  std::string name;
  TableKind kind;
};
const std::vector<KindName>& kind_names() {
  static const std::vector<KindName> names = [] {
    std::vector<KindName> v;
    for (const Family* f : detail::families())
      for (TableKind k : f->kinds()) v.push_back({f->kind_name(k), k});
    return v;
  }();
  return names;
}

using detail::join;

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
  for (const KindName& k : kind_names())
    if (name == k.name) return k.kind;
  std::vector<std::string> names;
  for (const KindName& k : kind_names()) names.push_back(k.name);
  throw Error("unknown table kind '" + name.substr(0, 60) + "' (known: " + join(names) + ")");
}

const char* table_kind_name(TableKind kind) {
  for (const KindName& k : kind_names())
    if (k.kind == kind) return k.name.c_str();
  return "?";
}

const std::vector<TableKind>& table_kinds() {
  static const std::vector<TableKind> kinds = [] {
    std::vector<TableKind> v;
    for (const KindName& k : kind_names()) v.push_back(k.kind);
    return v;
  }();
  return kinds;
}

const std::vector<TableCommandText>& table_commands() {
  static const std::vector<TableCommandText> commands = [] {
    std::vector<TableCommandText> v;
    for (const Family* f : detail::families()) {
      const detail::CommandText c = f->command_text();
      v.push_back({f->command(), c.usage, c.description, c.example});
    }
    return v;
  }();
  return commands;
}

std::string table_kind_command(TableKind kind) { return family_of(kind).command(); }

std::string table_kind_summary(TableKind kind) { return family_of(kind).summary(kind); }

bool table_kind_uses_environment(TableKind kind) { return family_of(kind).uses_environment(); }

bool table_kind_streams(TableKind kind) { return family_of(kind).streams(); }

bool table_needs_device(const TableRequest& t) { return family_of(t.kind).needs_device(t); }

std::string table_kind_default_pixel(TableKind kind) { return family_of(kind).default_pixel(); }

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

bool TableRequest::was_given(const std::string& name) const {
  return std::find(given.begin(), given.end(), name) != given.end();
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

TableExample table_kind_example(TableKind kind) {
  TableExample e = family_of(kind).example(kind);
  e.request.kind = kind;
  validate_table(e.request);
  return e;
}

// ---- Schemas and validation ----------------------------------------------------------------------

const std::vector<ParamDef>& table_schema(TableKind kind) { return family_of(kind).schema(kind); }

const std::vector<std::string>& table_common_fields() {
  static const std::vector<std::string> fields = {"kind",   "output",      "format",       "pixel",    "precision",
                                                  "device", "environment", "requested_by", "materials"};
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
  // Old and short spellings (aliases) to the schema's names, before anything reads or records them.
  canonicalize_params(t.params, schema, naming.cli || naming.prefix.empty() ? "" : naming.prefix + ".", naming.cli);
  for (auto& g : t.given)
    if (const ParamDef* d = find_param_def_or_alias(schema, g)) g = d->name;
  for (const auto& p : t.params)
    if (!find_param_def(schema, p.name)) {
      std::vector<std::string> names = table_common_fields();
      for (const auto& d : schema) names.push_back(d.name);
      throw Error(field(p.name) + ": unknown field for kind '" + table_kind_name(t.kind) + "' (expected " +
                  join(names) + ")");
    }
  // Types and ranges, then defaults, in the schema's order.
  if (t.given.empty())
    for (const auto& p : t.params) t.given.push_back(p.name);
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
  if (t.pixel == "astc4x4" || t.pixel == "astc6x6") {
    // ASTC HDR (io/astc_ktx2): the prefiltered chains' KTX2 (docs/ENGINES.md); the output's
    // container is checked with the family's (check_cube_output)
    if (t.kind != TableKind::Prefilter)
      throw Error(field("pixel") + ": " + t.pixel +
                  " is for prefiltered chains written as .ktx2 (kind prefilter), not " + table_kind_name(t.kind) +
                  " (give f16 or f32)");
  } else if (t.pixel != "f16" && t.pixel != "f32") {
    throw Error(field("pixel") + ": must be f16, f32, or for a prefilter chain's .ktx2 astc4x4 or astc6x6 (got '" +
                t.pixel.substr(0, 60) + "')");
  }
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

const char* table_size_param(TableKind kind) { return kind == TableKind::Prefilter ? "chain_size" : "size"; }

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

void check_backend(const TableRequest& t, Backend& backend) {
  if (t.precision != Precision::Fp64) return;
  if (const Device* d = backend.device(); d && !d->info().fp64)
    throw Error("--precision fp64: device '" + d->info().name + "' has no fp64 support (cl_khr_fp64); use fp32, " +
                "another device (brdfbake devices) or --device reference");
}

namespace {

// The values of `data` that are not finite: how many, and the index of the first.
template <class T>
size_t count_not_finite(const std::vector<T>& data, size_t* first) {
  size_t n = 0;
  for (size_t i = 0; i < data.size(); ++i)
    if (!std::isfinite(data[i])) {
      if (n++ == 0) *first = i;
    }
  return n;
}

// No NaN or Inf reaches an output (docs/RELIABILITY.md, "Outputs"): a result holding one is refused
// before anything is written. The families keep their inputs finite and in range, so this is a
// failure of the bake (exit 1), with where it is for a bug report.
void check_finite(const BakeResult& r) {
  size_t first = 0, bad = 0;
  std::string where;
  if (const Table* t = r.table()) {
    bad = count_not_finite(t->data, &first);
    if (bad) where = "cell " + std::to_string(first / std::max<size_t>(1, t->channels.size()));
  } else if (const CubeLevels* c = r.cube()) {
    for (size_t l = 0; l < c->levels.size() && !bad; ++l)
      if ((bad = count_not_finite(c->levels[l], &first))) where = "level " + std::to_string(l);
  } else if (const IrradianceResult* i = r.irradiance()) {
    if ((bad = count_not_finite(i->sh.radiance, &first) + count_not_finite(i->sh.irradiance_over_pi, &first)))
      where = "the SH coefficients";
    else if (!i->cube.levels.empty() && (bad = count_not_finite(i->cube.levels[0], &first)))
      where = "the irradiance cube";
  } else if (const MerlTable* m = r.merl()) {
    if ((bad = count_not_finite(m->values, &first))) where = "bin " + std::to_string(first);
  } else if (const EvalResult* e = r.eval()) {
    if ((bad = count_not_finite(e->values, &first))) where = "pair " + std::to_string(first / 3);
  }
  if (bad)
    throw RuntimeFailure(std::string(table_kind_name(r.kind)) + ": the result holds " + std::to_string(bad) +
                         (bad == 1 ? " value" : " values") + " that " + (bad == 1 ? "is" : "are") +
                         " not finite (first in " + where + "); nothing was written");
}

}  // namespace

BakeResult bake_table(const TableRequest& t, Backend& backend, const BakeInputs& inputs, const BakeProgress& progress) {
  const Family& family = family_of(t.kind);
  if (family.uses_environment() && !inputs.environment)
    throw Error(std::string(table_kind_name(t.kind)) + " needs an environment");
  check_backend(t, backend);
  throw_if_cancelled();
  const auto t0 = std::chrono::steady_clock::now();
  // Progress reports are where a stop request is honoured (engines report between launches). The
  // reference backends report from worker threads, which must not throw: they stop by themselves.
  const std::thread::id caller = std::this_thread::get_id();
  const BakeProgress report = [&progress, caller](double fraction, const std::string& step) {
    if (std::this_thread::get_id() == caller) throw_if_cancelled();
    if (progress) progress(fraction, step);
  };
  BakeResult r = family.bake(t, backend, inputs, report);
  r.kind = t.kind;
  r.device = backend.name();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Every parameter as baked: the request's, with what the family resolved (e.g. DFG samples).
  Params all = t.params;
  for (auto& p : r.parameters) {
    auto it = std::find_if(all.begin(), all.end(), [&](const Param& q) { return q.name == p.name; });
    if (it != all.end())
      it->value = p.value;
    else
      all.push_back(p);
  }
  r.parameters = std::move(all);
  return r;
}

namespace detail {

std::optional<WrittenBytes> write_result_bytes(const BakeResult& r, const TableRequest& t) {
  check_finite(r);
  return family_of(t.kind).write_bytes(r, t);
}

}  // namespace detail

WriteReport write_result(const BakeResult& r, const TableRequest& t, const std::string& path) {
  check_finite(r);
  if (path == "-") return family_of(t.kind).write(r, t, path);
  io::ParentFolders parents(path);
  WriteReport w = family_of(t.kind).write(r, t, path);
  parents.keep();
  return w;
}

}  // namespace brdfbake
