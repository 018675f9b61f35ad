// The DFG family (kinds ggx, ggx-multiscatter, charlie): split-sum lookup tables.
// Engine: host/src/dfg_lut.cpp and kernels/dfg_lut.cl; reference: host/reference/src/dfg.cpp;
// tests: tests/device/test_dfg_lut.cpp, tests/reference/test_dfg_reference.cpp.
#include <algorithm>

#include "brdfbake/lut.hpp"
#include "families/family.hpp"

namespace brdfbake::detail {
namespace {

LutKind lut_kind_of(TableKind k) {
  return k == TableKind::Ggx ? LutKind::Ggx : k == TableKind::GgxMultiscatter ? LutKind::GgxMultiscatter : LutKind::Charlie;
}

// What a shader does with each kind's channels.
std::string runtime_formula(TableKind k) {
  switch (k) {
    case TableKind::Ggx: return "specular = F0 * scale + F90 * bias";
    case TableKind::GgxMultiscatter: return "specular = mix(bias, albedo, F0) * (1 + F0 * (1 / albedo - 1))";
    default: return "sheen = sheen_color * albedo (scale the base layer by 1 - max(sheen_color) * albedo)";
  }
}

class DfgLutFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override { return {TableKind::Ggx, TableKind::GgxMultiscatter, TableKind::Charlie}; }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    return grid_bytes(t.number("size") * t.number("height", t.number("size")), 3);
  }
  std::string command() const override { return "lut"; }
  std::string summary(TableKind k) const override {
    switch (k) {
      case TableKind::Ggx: return "split-sum DFG table: GGX scale and bias, Burley diffuse albedo";
      case TableKind::GgxMultiscatter: return "split-sum DFG table for energy compensation: bias, albedo, diffuse";
      default: return "Charlie sheen directional albedo table";
    }
  }

  const std::vector<ParamDef>& schema(TableKind k) const override {
    static const LutSpec d;
    using T = ParamType;
    static const std::vector<ParamDef> ggx = {
        ParamDef("size", T::Int, "cells along n_dot_v (and roughness unless height is given)").range(1, kLutMaxSize).def(double(d.width)),
        ParamDef("height", T::Int, "cells along roughness").range(1, kLutMaxSize).defaults_to("size"),
        ParamDef("samples", T::Int, "evaluations per texel (default: the calibrated count for a 1e-4 bound); not with max_error")
            .range(1, kLutMaxSamples),
        ParamDef("max_error", T::Number, "the fewest calibrated samples whose measured max error is below this").above(0, 1),
        ParamDef("estimator", T::Name, "how each texel's integral is estimated (uniform: charlie only; vndf: ggx only)")
            .one_of({"quadrature", "vndf", "ndf", "uniform"}).def(std::string(estimator_name(d.estimator))),
    };
    static const std::vector<ParamDef> charlie = [] {
      std::vector<ParamDef> s = ggx;
      s.push_back(ParamDef("sheen_visibility", T::Name, "the Charlie visibility term")
                      .one_of({"estevez-kulla", "neubelt"}).def(std::string(sheen_visibility_name(d.sheen_visibility))));
      return s;
    }();
    return k == TableKind::Charlie ? charlie : ggx;
  }

  void check(TableRequest& t, const FieldName& name) const override {
    if (!t.find("height")) t.set("height", t.number("size"));
    if (t.find("samples") && t.find("max_error"))
      throw FieldError("max_error", "give " + name("samples") + " or " + name("max_error") + ", not both");
    try {
      resolve_lut_spec(spec_of(t));
    } catch (const Error& e) {
      throw FieldError(t.find("samples") ? "samples" : t.find("max_error") ? "max_error" : "estimator", e.what());
    }
  }

  std::string default_output(const TableRequest& t) const override {
    std::string kind = table_kind_name(t.kind);
    std::replace(kind.begin(), kind.end(), '-', '_');
    std::string stem = "dfg_" + kind;
    if (t.kind == TableKind::Charlie && t.text("sheen_visibility") != "estevez-kulla") stem += "_" + t.text("sheen_visibility");
    stem += "_" + fmt_number(t.number("size"), "%.0f");
    if (t.number("height") != t.number("size")) stem += "x" + fmt_number(t.number("height"), "%.0f");
    return stem + (t.format.empty() ? ".exr" : output_extension(t));
  }
  OutputFormats formats(const TableRequest&) const override { return table_formats(); }

  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs&, const BakeProgress& progress) const override {
    const LutSpec spec = spec_of(t);
    LutTiming timing;
    BakeResult r;
    Table table = backend.lut(spec, &timing, [&](double f) { progress(f, ""); });
    const LutSpec resolved = resolve_lut_spec(spec);
    if (backend.is_reference()) {
      r.error_bound = kLutReferenceBound;
      r.error_bound_definition = table.meta("error_bound_definition");
    } else {
      int measured_at = 0;
      const double bound = lut_error_bound(resolved.kind, resolved.estimator, resolved.precision, resolved.samples, &measured_at);
      if (bound >= 0) r.error_bound = bound;
      r.error_bound_definition = table.meta("error_bound_definition");
      if (bound >= 0 && measured_at != resolved.samples)
        r.details.push_back({"error_bound_measured_at", table.meta("error_bound_measured_at")});
      r.parameters.push_back({"samples", double(resolved.samples)});
    }
    r.details.push_back({"channels", table.meta("channels")});
    r.details.push_back({"runtime", runtime_formula(t.kind)});
    r.device_seconds = timing.device_seconds;
    r.summary = std::string(table_kind_name(t.kind)) + " " + std::to_string(table.width) + "x" +
                std::to_string(table.height) + ", " + table.meta("estimator") + ", " + table.meta("samples") +
                " samples, " + table.meta("precision") + ", error bound " +
                (r.error_bound ? fmt_number(*r.error_bound, "%.2g") : std::string("not measured")) + ", " +
                fmt_number(timing.wall_seconds, "%.3f") + " s (device " + fmt_number(timing.device_seconds, "%.3f") +
                " s); runtime: " + runtime_formula(t.kind);
    r.artifact = std::move(table);
    return r;
  }

  void write(const BakeResult& r, const TableRequest& t, const std::string& path) const override {
    write_table_result(*r.table(), t, path);
  }

 private:
  static LutSpec spec_of(const TableRequest& t) {
    LutSpec s;
    s.kind = lut_kind_of(t.kind);
    s.width = static_cast<int>(t.number("size"));
    s.height = static_cast<int>(t.number("height", t.number("size")));
    s.samples = static_cast<int>(t.number("samples", 0));
    s.max_error = t.number("max_error", 0);
    s.estimator = estimator_from_name(t.text("estimator"));
    if (t.kind == TableKind::Charlie) s.sheen_visibility = sheen_visibility_from_name(t.text("sheen_visibility"));
    s.precision = t.precision;
    return s;
  }
};

}  // namespace

const Family& dfg_lut_family() {
  static const DfgLutFamily f;
  return f;
}

}  // namespace brdfbake::detail
