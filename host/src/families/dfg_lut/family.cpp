// The DFG family (kinds ggx, ggx-multiscatter, charlie): split-sum lookup tables. Its descriptor:
// the schema bound to LutSpec, the rules across fields, names, the bake with its lookup error, and
// the registration of its kernels. Model: model.cpp, calibration.cpp; kernels: opencl.cpp
// (kernels/dfg_lut.cl), reference.cpp (host/reference/src/dfg_lut.cpp); tests:
// tests/device/test_dfg_lut.cpp, tests/reference/test_dfg_reference.cpp.
#include "families/family.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "brdfbake/dfg_lut.hpp"
#include "families/dfg_lut/kernel.hpp"
#include "families/dfg_lut/model.hpp"
#include "families/kernels.hpp"
#include "families/spec_schema.hpp"

namespace brdfbake::detail {
namespace {

LutKind lut_kind_of(TableKind k) {
  return k == TableKind::Ggx               ? LutKind::Ggx
         : k == TableKind::GgxMultiscatter ? LutKind::GgxMultiscatter
                                           : LutKind::Charlie;
}

// What a shader does with each kind's channels.
std::string runtime_formula(TableKind k) {
  switch (k) {
    case TableKind::Ggx:
      return "specular = F0 * scale + F90 * bias";
    case TableKind::GgxMultiscatter:
      return "specular = mix(bias, albedo, F0) * (1 + F0 * (1 / albedo - 1))";
    default:
      return "sheen = sheen_color * albedo (scale the base layer by 1 - max(sheen_color) * albedo)";
  }
}

// The most the output's encoding can add to a value in [0, 2] (the DFG channels' range; abs below 1,
// relative above): binary16 rounds to 11 significant bits, 16-bit UNORM to 1/65535, RGBE's shared
// exponent leaves the smaller channels 8 bits of the largest; float32 and 9-digit text add nothing.
double storage_allowance(const TableRequest& t) {
  if (t.output.empty() || t.output == "-") return 0.0;
  switch (table_output_format(t)) {
    case TableFormat::Ktx2:
    case TableFormat::CHeader:
      return t.pixel == "f32" ? 0.0 : std::ldexp(1.0, -11);
    case TableFormat::Png:
      return 0.5 / 65535.0;
    case TableFormat::Hdr:
      return std::ldexp(1.0, -7);
    default:
      return 0.0;
  }
}

std::string storage_name(const TableRequest& t) {
  switch (table_output_format(t)) {
    case TableFormat::Ktx2:
    case TableFormat::CHeader:
      return "binary16";
    case TableFormat::Png:
      return "16-bit PNG";
    case TableFormat::Hdr:
      return "RGBE (.hdr)";
    default:
      return "this format";
  }
}

// The schema of a kind, bound to LutSpec: GGX's parameters, Charlie's with sheen_visibility, and the
// output parameters of every table.
SpecSchema<LutSpec> lut_schema(bool charlie) {
  static const LutSpec d;
  using T = ParamType;
  SpecSchema<LutSpec> s;
  s.common("kind", "kind", [](LutSpec& l, const TableRequest& t) { l.kind = lut_kind_of(t.kind); })
      .bind(&LutSpec::width, "width",
            ParamDef("size", T::Int, "cells along n_dot_v (and roughness unless height is given)")
                .range(1, kLutMaxSize)
                .def(double(d.width)))
      .bind(&LutSpec::height, "height",
            ParamDef("height", T::Int, "cells along roughness").range(1, kLutMaxSize).defaults_to("size"))
      .bind(&LutSpec::samples, "samples",
            ParamDef("samples", T::Int,
                     "evaluations per texel (default: the calibrated count for a 1e-4 bound); not with max_error")
                .range(1, kLutMaxSamples))
      // max_error bounds the delivered values: the integration gets what the output's storage leaves.
      .bind("max_error",
            ParamDef("max_error", T::Number, "the fewest calibrated samples whose measured max error is below this")
                .above(0, 1),
            [](LutSpec& l, const TableRequest& t) {
              if (t.find("max_error")) l.max_error = std::max(0.0, t.number("max_error") - storage_allowance(t));
            })
      .bind(&LutSpec::estimator, "estimator",
            ParamDef("estimator", T::Name,
                     "how each texel's integral is estimated (uniform: charlie only; vndf: ggx only)")
                .one_of(enum_names(kEstimatorNames))
                .def(std::string(estimator_name(d.estimator))),
            by_name(estimator_from_name))
      .common("precision", "precision", [](LutSpec& l, const TableRequest& t) { l.precision = t.precision; })
      .bind(&LutSpec::n_dot_v_axis, "n_dot_v_axis",
            ParamDef("n_dot_v_axis", T::Name,
                     "texels along n_dot_v: uniform, or sqrt (lookup u = sqrt(n_dot_v): more texels at grazing)")
                .one_of(enum_names(kLutAxisNames))
                .def(std::string(lut_axis_name(d.n_dot_v_axis))),
            by_name(lut_axis_from_name))
      .internal("roughness_axis", "measured: no separable mapping beats uniform (docs/BENCHMARKS.md)")
      .internal("n_dot_v", "explicit coordinates: tests and benches only")
      .internal("roughness", "explicit coordinates: tests and benches only");
  if (charlie)
    s.bind(&LutSpec::sheen_visibility, "sheen_visibility",
           ParamDef("sheen_visibility", T::Name, "the Charlie visibility term")
               .one_of(enum_names(kSheenVisibilityNames))
               .def(std::string(sheen_visibility_name(d.sheen_visibility))),
           by_name(sheen_visibility_from_name));
  else
    s.internal("sheen_visibility", "the charlie kind's parameter");
  std::vector<ParamDef> output;
  add_table_output_params(output);
  return s.params(output);
}

const SpecSchema<LutSpec>& lut_schema_of(TableKind k) {
  static const SpecSchema<LutSpec> ggx = lut_schema(false), charlie = lut_schema(true);
  return k == TableKind::Charlie ? charlie : ggx;
}

// What a shader's bilinear lookup of `table` misses: the table looked up at the lines between
// texel centres (and at both edges) against the backend's own evaluation there.
LookupError measure_lookup_error(const LutSpec& resolved, const Table& table, Backend& backend) {
  const std::vector<double> us = probe_coordinates(table.width), vs = probe_coordinates(table.height);
  LutSpec probe = resolved;  // the same estimator and sample count
  probe.max_error = 0.0;
  probe.n_dot_v.clear();
  probe.roughness.clear();
  for (double u : us) probe.n_dot_v.push_back(lut_axis_value(resolved.n_dot_v_axis, u));
  for (double v : vs) probe.roughness.push_back(lut_axis_value(resolved.roughness_axis, v));
  const Table truth = bake_lut(backend, probe);
  return bilinear_lookup_error(table, us, vs, truth);
}

// The measurement depends only on what is baked (the resolved spec) and where (the backend's
// device and precision), and the bake is deterministic: it is made once per process for each and
// remembered, since its probe is a second bake of about the table's size (on a warm server, half
// of a new table's device time; docs/BENCHMARKS.md, "POST /v1/tables"). The numbers, and so every
// byte written, are those a fresh measurement gives. (A request's table is always at the cell
// centres of its axes: the resolved spec's coordinates follow from the fields in the key.)
LookupError lookup_error_once(const LutSpec& resolved, const Table& table, Backend& backend) {
  const std::string key =
      backend.name() + "|" + precision_name(backend.result_precision(resolved.precision)) + "|" +
      std::to_string(int(resolved.kind)) + "|" + std::to_string(resolved.width) + "x" +
      std::to_string(resolved.height) + "|" + std::to_string(resolved.samples) + "|" +
      std::to_string(int(resolved.estimator)) + "|" + std::to_string(int(resolved.sheen_visibility)) + "|" +
      std::to_string(int(resolved.n_dot_v_axis)) + "|" + std::to_string(int(resolved.roughness_axis));
  static std::mutex mutex;
  static std::map<std::string, LookupError> measured;
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = measured.find(key); it != measured.end()) return it->second;
  }
  const LookupError e = measure_lookup_error(resolved, table, backend);
  std::lock_guard<std::mutex> lock(mutex);
  if (measured.size() >= 4096) measured.clear();  // a few dozen bytes each: a bound, not a policy
  measured.emplace(key, e);
  return e;
}

// What a shader's bilinear lookup of `table` misses between texel centres: the table looked up at
// the lines between centres (and at both edges) against the backend's own evaluation there; both
// are within the integration bound `bound` of the converged values. Recorded in the table's
// metadata and `r`'s details; returns the summary's clause.
std::string add_lookup_error(Table& table, const LutSpec& resolved, Backend& backend, double bound, BakeResult& r) {
  const LookupError e = lookup_error_once(resolved, table, backend);
  const double margin = 2.0 * bound;
  const std::string interior = fmt_number(e.interior + margin, "%.3g"), edge = fmt_number(e.edge + margin, "%.3g");
  r.details.push_back({"interpolation_error", interior});
  r.details.push_back({"edge_error", edge});
  table.set_meta("interpolation_error", interior);
  table.set_meta("interpolation_error_definition",
                 "max |bilinear lookup - converged value| (abs below 1, relative above) on the lines between "
                 "texel centres: measured against the same estimator there, plus twice its integration bound");
  table.set_meta("edge_error", edge);
  table.set_meta("edge_error_definition",
                 "the same within half a texel of the table's edges (n_dot_v or roughness near 0 or 1), where "
                 "clamp to edge returns the outermost texel");
  return ", bilinear lookup within " + fmt_number(e.interior + margin, "%.2g") + " (" +
         fmt_number(e.edge + margin, "%.2g") + " at the edges)";
}

class DfgLutFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override {
    return {TableKind::Ggx, TableKind::GgxMultiscatter, TableKind::Charlie};
  }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    return grid_bytes(t.number("size") * t.number("height", t.number("size")), 3);
  }
  std::string command() const override { return "lut"; }
  CommandText command_text() const override {
    return {"bake a split-sum DFG lookup table (ggx, ggx-multiscatter, charlie)",
            "Bake a split-sum DFG lookup table (ggx, ggx-multiscatter, charlie)",
            "brdfbake lut --kind ggx-multiscatter --size 128 -o dfg.exr"};
  }
  std::string kind_name(TableKind k) const override {
    return k == TableKind::Ggx ? "ggx" : k == TableKind::GgxMultiscatter ? "ggx-multiscatter" : "charlie";
  }
  std::string summary(TableKind k) const override {
    switch (k) {
      case TableKind::Ggx:
        return "split-sum DFG table: GGX scale and bias, Burley diffuse albedo";
      case TableKind::GgxMultiscatter:
        return "split-sum DFG table for energy compensation: bias, albedo, diffuse";
      default:
        return "Charlie sheen directional albedo table";
    }
  }

  const std::vector<ParamDef>& schema(TableKind k) const override { return lut_schema_of(k).schema(); }
  std::vector<SpecField> spec_fields(TableKind k) const override { return lut_schema_of(k).fields(); }

  TableExample example(TableKind) const override {
    TableExample e;
    e.request.params = {{"size", 4.0}, {"samples", 256.0}};
    return e;
  }
  void register_kernels(KernelRegistry& r) const override {
    r.add<DfgLutKernel>(Platform::OpenCl, [](Backend& b) { return make_opencl_dfg_lut(*b.device()); });
    r.add<DfgLutKernel>(Platform::Reference, [](Backend&) { return make_reference_dfg_lut(); });
  }

  void check(TableRequest& t, const FieldName& name) const override {
    if (!t.find("height")) t.set("height", t.number("size"));
    if (t.find("samples") && t.find("max_error"))
      throw FieldError("max_error", "give " + name("samples") + " or " + name("max_error") + ", not both");
    const double texels = t.number("size") * t.number("height");
    if (texels > double(kLutMaxTexels))
      throw FieldError(t.number("height") != t.number("size") ? "height" : "size",
                       "a " + fmt_number(t.number("size")) + "x" + fmt_number(t.number("height")) + " table has " +
                           fmt_number(texels) + " texels; at most " + fmt_number(double(kLutMaxTexels)) +
                           " (8192x8192)");
    resolve_or_explain(t);
    const LutSpec resolved = resolve_lut_spec(spec_of(t));
    // The whole bake's work is bounded too: a huge table at a huge sample count would run for days.
    const double per_texel = resolved.samples;  // evaluations per texel, whatever the estimator
    if (texels * per_texel > kLutMaxEvaluations)
      throw FieldError(t.find("samples") ? "samples" : "size",
                       "a " + fmt_number(t.number("size")) + "x" + fmt_number(t.number("height")) + " table at " +
                           fmt_number(resolved.samples) + " samples is " + fmt_number(texels * per_texel, "%.3g") +
                           " evaluations; at most " + fmt_number(kLutMaxEvaluations, "%.3g") + " (2^40): lower " +
                           name("samples") + " or " + name("size"));
  }

  std::string default_output(const TableRequest& t) const override {
    std::string kind = table_kind_name(t.kind);
    std::replace(kind.begin(), kind.end(), '-', '_');
    std::string stem = "dfg_" + kind;
    if (t.kind == TableKind::Charlie && t.text("sheen_visibility") != "estevez-kulla")
      stem += "_" + t.text("sheen_visibility");
    stem += "_" + fmt_number(t.number("size"), "%.0f");
    if (t.number("height") != t.number("size")) stem += "x" + fmt_number(t.number("height"), "%.0f");
    if (t.text("n_dot_v_axis") == "sqrt") stem += "_sqrt_nv";
    return stem + (t.format.empty() ? ".exr" : output_extension(t));
  }
  OutputFormats formats(const TableRequest&) const override { return table_formats(); }

  // max_error bounds the delivered values: the integration gets what the format's storage leaves.
  void check_output(const TableRequest& t, const FieldName& name) const override {
    Family::check_output(t, name);
    if (!t.find("max_error")) return;
    const double target = t.number("max_error");
    const double storage = storage_allowance(t);
    if (storage >= target)
      throw FieldError("max_error", fmt_number(target) + " cannot be delivered in " + storage_name(t) +
                                        " (its rounding alone is up to " + fmt_number(storage, "%.2g") +
                                        "): give pixel f32 (--pixel f32) or write .exr or .csv");
    resolve_or_explain(t);
  }

  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs&,
                  const BakeProgress& progress) const override {
    const LutSpec spec = spec_of(t);
    LutTiming timing;
    BakeResult r;
    Table table = bake_lut(backend, spec, &timing, [&](double f) { progress(f, ""); });
    const LutSpec resolved = resolve_lut_spec(spec);
    if (backend.is_reference()) {
      r.error_bound = kLutReferenceBound;
      r.error_bound_definition = table.meta("error_bound_definition");
    } else {
      int measured_at = 0;
      const double bound =
          lut_error_bound(resolved.kind, resolved.estimator, resolved.precision, resolved.samples, &measured_at);
      if (bound >= 0) r.error_bound = bound;
      r.error_bound_definition = table.meta("error_bound_definition");
      if (bound >= 0 && measured_at != resolved.samples)
        r.details.push_back({"error_bound_measured_at", table.meta("error_bound_measured_at")});
      r.parameters.push_back({"samples", double(resolved.samples)});
    }
    const std::string interpolation = add_lookup_error(table, resolved, backend, r.error_bound.value_or(0.0), r);
    r.details.push_back({"channels", table.meta("channels")});
    r.details.push_back({"runtime", runtime_formula(t.kind)});
    r.device_seconds = timing.device_seconds;
    r.summary = std::string(table_kind_name(t.kind)) + " " + std::to_string(table.width) + "x" +
                std::to_string(table.height) + ", " + table.meta("estimator") + ", " + table.meta("samples") +
                " samples, " + table.meta("precision") + ", integration error bound " +
                (r.error_bound ? fmt_number(*r.error_bound, "%.2g") : std::string("not measured")) + ", " +
                fmt_number(timing.wall_seconds, "%.3f") + " s (device " + fmt_number(timing.device_seconds, "%.3f") +
                " s)" + interpolation + "; runtime: " + runtime_formula(t.kind);
    r.artifact = std::move(table);
    return r;
  }

  WriteReport write(const BakeResult& r, const TableRequest& t, const std::string& path) const override {
    return write_table_result(*r.table(), t, path, r.error_bound,
                              t.find("max_error") ? std::optional<double>(t.number("max_error")) : std::nullopt);
  }
  std::optional<WrittenBytes> write_bytes(const BakeResult& r, const TableRequest& t) const override {
    return table_result_bytes(*r.table(), t, r.error_bound,
                              t.find("max_error") ? std::optional<double>(t.number("max_error")) : std::nullopt);
  }

 private:
  // resolve_lut_spec, its message naming the field and, for an unreachable max_error, what reaches it.
  static void resolve_or_explain(const TableRequest& t) {
    try {
      resolve_lut_spec(spec_of(t));
    } catch (const Error& e) {
      std::string hint;
      if (t.find("max_error") && t.precision == Precision::Fp32) {
        LutSpec fp64 = spec_of(t);
        fp64.precision = Precision::Fp64;
        try {
          resolve_lut_spec(fp64);
          hint = "; precision fp64 (--precision fp64) reaches it";
        } catch (const Error&) {
        }
      }
      throw FieldError(t.find("samples")     ? "samples"
                       : t.find("max_error") ? "max_error"
                                             : "estimator",
                       e.what() + hint);
    }
  }

  static LutSpec spec_of(const TableRequest& t) { return lut_schema_of(t.kind).fill(t); }
};

}  // namespace

const Family& dfg_lut_family() {
  static const DfgLutFamily f;
  return f;
}

}  // namespace brdfbake::detail
