// The Fresnel family (kind fresnel): 1-D tables over cos_theta and 2-D tables over (cos_theta, F0 or
// IOR) for every model, exact and approximate. Its descriptor: the schema bound to FresnelSpec, the
// rules across fields, names, the bake with its measured bound, and the registration of its
// kernels. Model: names.cpp, resolve.cpp, conductor.cpp, metadata.cpp; errors and comparisons:
// errors.cpp, compare.cpp; kernels: opencl.cpp (kernels/fresnel.cl), reference.cpp
// (host/reference/src/fresnel.cpp); tests: tests/device/test_fresnel.cpp,
// tests/reference/test_fresnel_reference.cpp.
#include "families/family.hpp"

#include <algorithm>

#include "brdfbake/fresnel.hpp"
#include "families/fresnel/kernel.hpp"
#include "families/fresnel/model.hpp"
#include "families/kernels.hpp"
#include "families/spec_schema.hpp"

namespace brdfbake::detail {
namespace {

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (FresnelModel m : fresnel_models()) names.push_back(fresnel_model_name(m));
  return names;
}

// The schema, bound to FresnelSpec.
SpecSchema<FresnelSpec> make_fresnel_schema() {
  static const FresnelSpec d;
  using T = ParamType;
  using S = FresnelSpec;
  SpecSchema<FresnelSpec> s;
  s.bind(&S::model, "model", ParamDef("model", T::Name, "the Fresnel model").one_of(model_names()).needed(),
         by_name(fresnel_model_from_name))
      .bind(&S::material, "material",
            ParamDef("material", T::Name, "a measured material preset (brdfbake fresnel --list-materials)"))
      .bind(&S::f0, "f0", ParamDef("f0", T::Color, "schlick, f82-tint: reflectance at normal incidence").range(0, 1))
      .bind(&S::f90, "f90",
            ParamDef("f90", T::Color, "schlick: reflectance at grazing incidence").range(0, 1).defaults_to("1"))
      .bind(&S::f82_tint, "f82_tint",
            ParamDef("f82", T::Color, "f82-tint: the F82 tint (1 is plain Schlick)").range(0, 1e3))
      .bind(&S::base_color, "base_color", ParamDef("base_color", T::Color, "schlick-metallic: base colour").range(0, 1))
      .bind(&S::metallic, "metallic", ParamDef("metallic", T::Number, "schlick-metallic: metallic").range(0, 1))
      .bind(&S::dielectric_f0, "dielectric_f0",
            ParamDef("dielectric_f0", T::Number, "schlick-metallic: the dielectric F0").range(0, 1).defaults_to("0.04"))
      .bind(&S::ior, "ior",
            ParamDef("ior", T::Color, "schlick-ior, dielectric: index of the far side").above(0, kFresnelMaxIndex))
      .bind(&S::ior_outside, "ior_outside",
            ParamDef("ior_outside", T::Number, "schlick-ior, dielectric: index of the side the light comes from")
                .above(0, kFresnelMaxIndex)
                .defaults_to("1"))
      .bind(&S::n, "n", ParamDef("n", T::Color, "conductor: real part of the complex index").above(0, kFresnelMaxIndex))
      .bind(&S::k, "k", ParamDef("k", T::Color, "conductor: extinction coefficient").range(0, kFresnelMaxIndex))
      .bind(&S::bias, "bias", ParamDef("bias", T::Number, "empirical: bias"))
      .bind(&S::scale, "scale", ParamDef("scale", T::Number, "empirical: scale"))
      .bind(&S::power, "power", ParamDef("power", T::Number, "empirical: power").range(0, HUGE_VAL))
      .bind(&S::table, "table",
            ParamDef("table", T::Name, "1d (cos_theta; r, g, b) or 2d (cos_theta x f0 or ior; one channel)")
                .one_of(enum_names(kFresnelTableKindNames))
                .def(std::string(fresnel_table_kind_name(d.table))),
            by_name(fresnel_table_kind_from_name))
      .bind(&S::size, "size",
            ParamDef("size", T::Int, "cells along cos_theta").range(1, double(kFresnelMaxCells)).def(double(d.size)))
      .bind(&S::height, "height",
            ParamDef("height", T::Int, "2d: cells along the y axis")
                .range(1, double(kFresnelMaxCells))
                .defaults_to("size"))
      .bind(&S::endpoints, "endpoints",
            ParamDef("endpoints", T::Flag,
                     "cos_theta = i / (N - 1), so that 0 and 1 are cells (default: cell centres (i + 0.5) / N)")
                .def(d.endpoints))
      .bind(&S::range, "range",
            ParamDef("range", T::Range, "2d: the y range lo,hi").defaults_to("0,1 for f0 and 1,3 for ior"),
            [](const ParamValue& v) {
              const auto& r = std::get<std::vector<double>>(v);
              return std::make_pair(r[0], r[1]);
            })
      .param(ParamDef("vs_exact", T::Flag,
                      "add err_r,err_g,err_b = value - the exact model for the same material (.csv or .h)")
                 .def(false))
      .common("precision", "precision", [](FresnelSpec& f, const TableRequest& t) { f.precision = t.precision; })
      .internal("cos_theta", "explicit cosines: tests only");
  std::vector<ParamDef> output;
  add_table_output_params(output);
  return s.params(output);
}

const SpecSchema<FresnelSpec>& fresnel_schema() {
  static const SpecSchema<FresnelSpec> s = make_fresnel_schema();
  return s;
}

class FresnelFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override { return {TableKind::Fresnel}; }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    // 1d: r, g, b (and three error columns with vs_exact); 2d: one channel over size x height.
    if (t.text("table") == "2d") return grid_bytes(t.number("size") * t.number("height", t.number("size")), 1);
    return grid_bytes(t.number("size"), t.flag("vs_exact") ? 6 : 3);
  }
  std::string command() const override { return "fresnel"; }
  TableExample example(TableKind) const override {
    TableExample e;
    e.request.params = {{"model", std::string("conductor")}, {"material", std::string("gold")}, {"size", 16.0}};
    return e;
  }
  CommandText command_text() const override {
    return {"bake a Fresnel table (exact and approximate models), compare the models",
            "Bake a Fresnel reflectance table, or compare the models",
            "brdfbake fresnel --model conductor --material gold -o gold.exr"};
  }
  std::string summary(TableKind) const override {
    return "a Fresnel reflectance table: exact dielectric and conductor, Schlick and its variants, F82 tint";
  }

  const std::vector<ParamDef>& schema(TableKind) const override { return fresnel_schema().schema(); }
  std::vector<SpecField> spec_fields(TableKind) const override { return fresnel_schema().fields(); }
  void register_kernels(KernelRegistry& r) const override {
    r.add<FresnelKernel>(Platform::OpenCl, [](Backend& b) { return make_opencl_fresnel(*b.device()); });
    r.add<FresnelKernel>(Platform::Reference, [](Backend&) { return make_reference_fresnel(); });
  }

  void check(TableRequest& t, const FieldName& name) const override {
    const FresnelSpec s = spec_of(t);
    try {
      validate_fresnel_spec(s);
      if (t.flag("vs_exact")) exact_fresnel_spec(s);
    } catch (const Error& e) {
      throw FieldError("", e.what());
    }
    if (t.flag("vs_exact") && !t.output.empty() && output_extension(t) != ".csv" && output_extension(t) != ".h")
      throw FieldError("output", name("vs_exact") + " adds three error columns: write .csv or .h");
  }

  std::string default_output(const TableRequest& t) const override {
    std::string model = t.text("model");
    std::replace(model.begin(), model.end(), '-', '_');
    std::string stem = "fresnel_" + model;
    if (t.text("table") == "2d") stem += "_2d";
    if (!t.text("material").empty()) stem += "_" + t.text("material");
    if (const ParamValue* v = t.find("ior"))  // schlick-ior's name already ends in "ior"
      stem += (model.size() >= 3 && model.compare(model.size() - 3, 3, "ior") == 0 ? "" : "_ior") + name_part(*v);
    if (const ParamValue* v = t.find("ior_outside")) stem += "_from" + name_part(*v);
    if (const ParamValue* v = t.find("f0")) stem += "_f0_" + name_part(*v);
    if (const ParamValue* v = t.find("f82")) stem += "_f82_" + name_part(*v);
    if (const ParamValue* v = t.find("n")) stem += "_n" + name_part(*v);
    if (const ParamValue* v = t.find("k")) stem += "_k" + name_part(*v);
    if (const ParamValue* v = t.find("base_color")) stem += "_base" + name_part(*v);
    if (const ParamValue* v = t.find("metallic")) stem += "_metallic" + name_part(*v);
    if (t.flag("vs_exact")) stem += "_vs_exact";
    return stem + (t.format.empty() ? (t.flag("vs_exact") ? ".csv" : ".exr") : output_extension(t));
  }
  OutputFormats formats(const TableRequest&) const override { return table_formats(); }

  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs&, const BakeProgress&) const override {
    const FresnelSpec spec = spec_of(t);
    FresnelTiming timing;
    BakeResult r;
    Table table = bake_fresnel(backend, spec, &timing);
    if (backend.is_reference()) {
      r.error_bound = 0.0;
      r.error_bound_definition = "the scalar double reference itself (stored as float32)";
    } else {
      r.error_bound = fresnel_error(table, bake_fresnel_reference(spec)).max_abs;
      r.error_bound_definition =
          "max |table - scalar double reference| over every cell and channel, measured when the table was baked";
    }
    table.set_meta("error_bound", fmt_number(*r.error_bound, "%.3g"));
    table.set_meta("error_bound_definition", r.error_bound_definition);
    if (t.flag("vs_exact")) {
      table = with_error_columns(table, bake_fresnel_reference(exact_fresnel_spec(spec)));
      r.details.push_back({"error_vs_exact_max_abs", table.meta("error_max_abs")});
      r.details.push_back({"error_vs_exact_mean_abs", table.meta("error_mean_abs")});
    }
    r.device_seconds = timing.device_seconds;
    r.summary = table.meta("model") + (spec.material.empty() ? "" : " " + spec.material) + " " +
                std::to_string(table.width) + "x" + std::to_string(table.height) + ", " + table.meta("precision") +
                ", max |table - reference| " + fmt_number(*r.error_bound, "%.2g") + ", " +
                fmt_number(timing.wall_seconds, "%.3f") + " s (device " +
                fmt_number(timing.device_seconds * 1e3, "%.3f") + " ms)" +
                (t.flag("vs_exact") ? ", max |error| vs exact " + table.meta("error_max_abs") : "");
    r.artifact = std::move(table);
    return r;
  }

  WriteReport write(const BakeResult& r, const TableRequest& t, const std::string& path) const override {
    return write_table_result(*r.table(), t, path, r.error_bound);
  }
  std::optional<WrittenBytes> write_bytes(const BakeResult& r, const TableRequest& t) const override {
    return table_result_bytes(*r.table(), t, r.error_bound);
  }

 private:
  static FresnelSpec spec_of(const TableRequest& t) { return fresnel_schema().fill(t); }
};

}  // namespace

const Family& fresnel_family() {
  static const FresnelFamily f;
  return f;
}

}  // namespace brdfbake::detail
