// The thin-film family (kind thin-film): interference Fresnel over (cos_theta, film thickness) for
// KHR_materials_iridescence (Belcour & Barla 2017). Its descriptor: the schema bound to
// ThinFilmSpec, the rules across fields, names, the bake with its measured bound, and the
// registration of its kernels. Model: model.cpp; kernels: opencl.cpp (kernels/thin_film.cl),
// reference.cpp (host/reference/src/thin_film.cpp); tests: tests/device/test_thin_film.cpp,
// tests/reference/test_thin_film_reference.cpp.
#include "families/family.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/thin_film.hpp"
#include "families/kernels.hpp"
#include "families/spec_schema.hpp"
#include "families/thin_film/kernel.hpp"

namespace brdfbake::detail {
namespace {

// The iridescence model is not bounded by 1: KHR_materials_iridescence's evaluation (the glTF
// Sample Viewer's evalIridescence, which we follow) clamps its result below 0 only, and its Airy
// sum with Schlick amplitudes and the XYZ to Rec. 709 conversion of the spectral integral exceed 1
// near grazing angles on bright bases (an F0 of 0.95 gives 1.076). The values are the model's, kept;
// a renderer must know: "" when every value is at most 1, else where and how much.
std::string reflectance_above_one(const Table& t) {
  size_t cells = 0;
  float worst = 1.0f;
  int wi = 0, wj = 0, wc = 0;
  for (int j = 0; j < t.height; ++j)
    for (int i = 0; i < t.width; ++i) {
      bool above = false;
      for (int c = 0; c < t.channel_count(); ++c) {
        const float v = t.data[(size_t(j) * size_t(t.width) + size_t(i)) * t.channels.size() + size_t(c)];
        if (v > 1.0f) above = true;
        if (v > worst) worst = v, wi = i, wj = j, wc = c;
      }
      cells += above;
    }
  if (!cells) return "";
  return "reflectance above 1 in " + std::to_string(cells) + " of " +
         std::to_string(size_t(t.width) * size_t(t.height)) + " cells, at most " + fmt_number(worst, "%.4g") + " (" +
         t.channels[size_t(wc)] + " at cos_theta " + fmt_number(t.x[size_t(wi)], "%.4g") +
         (t.y.empty() ? "" : ", thickness " + fmt_number(t.y[size_t(wj)], "%.4g") + " nm") +
         "): the KHR_materials_iridescence model clamps only below 0; clamp to 1 where a renderer needs a reflectance";
}

std::string name_number(double v) { return fmt_number(v, "%.6g"); }

// The schema, bound to ThinFilmSpec.
SpecSchema<ThinFilmSpec> make_thin_film_schema() {
  static const ThinFilmSpec d;
  using T = ParamType;
  using S = ThinFilmSpec;
  SpecSchema<ThinFilmSpec> s;
  s.bind(&S::film_ior, "film_ior",
         ParamDef("film_ior", T::Number, "the film's index (iridescenceIor)").range(1, 10).def(d.film_ior))
      .bind(&S::base_ior, "base_ior",
            ParamDef("base_ior", T::Number, "a dielectric base: its index (not with base_f0)").range(1, 10))
      .bind(&S::base_f0, "base_f0",
            ParamDef("base_f0", T::Color, "a base given by its F0, e.g. a metal's colour (not with base_ior)")
                .range(0, 1))
      .bind(&S::outside_ior, "outside_ior",
            ParamDef("outside_ior", T::Number, "the medium above the film").range(1, 10).def(d.outside_ior))
      .bind(&S::thickness_min, "thickness_min",
            ParamDef("thickness_min", T::Number, "thinnest film, nm (iridescenceThicknessMinimum)")
                .range(0, 1e5)
                .def(d.thickness_min))
      .bind(&S::thickness_max, "thickness_max",
            ParamDef("thickness_max", T::Number, "thickest film, nm (iridescenceThicknessMaximum)")
                .range(0, 1e5)
                .def(d.thickness_max))
      .bind(&S::width, "width", ParamDef("size", T::Int, "cells along cos_theta").range(1, 8192).def(double(d.width)))
      .bind(&S::height, "height",
            ParamDef("height", T::Int, "cells along the thickness")
                .range(1, 8192)
                .defaults_to("size, or 1 when thickness_min = thickness_max"))
      .common("precision", "precision", [](ThinFilmSpec& f, const TableRequest& t) { f.precision = t.precision; });
  std::vector<ParamDef> output;
  add_table_output_params(output);
  return s.params(output);
}

const SpecSchema<ThinFilmSpec>& thin_film_schema() {
  static const SpecSchema<ThinFilmSpec> s = make_thin_film_schema();
  return s;
}

class ThinFilmFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override { return {TableKind::ThinFilm}; }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    return grid_bytes(t.number("size") * t.number("height", t.number("size")), 3);
  }
  std::string command() const override { return "thin-film"; }
  TableExample example(TableKind) const override {
    TableExample e;
    e.request.params = {{"base_ior", 1.5}, {"size", 4.0}};
    return e;
  }
  CommandText command_text() const override {
    return {"bake a thin-film interference Fresnel table (KHR_materials_iridescence)",
            "Bake a thin-film interference Fresnel table over (cos_theta, thickness) (KHR_materials_iridescence)",
            "brdfbake thin-film --film-ior 1.3 --base-ior 1.5 --thickness-min 100 --thickness-max 400 -o film.exr"};
  }
  std::string summary(TableKind) const override {
    return "thin-film interference Fresnel over (cos_theta, thickness) for KHR_materials_iridescence";
  }

  const std::vector<ParamDef>& schema(TableKind) const override { return thin_film_schema().schema(); }
  std::vector<SpecField> spec_fields(TableKind) const override { return thin_film_schema().fields(); }
  void register_kernels(KernelRegistry& r) const override {
    r.add<ThinFilmKernel>(Platform::OpenCl, [](Backend& b) { return make_opencl_thin_film(*b.device()); });
    r.add<ThinFilmKernel>(Platform::Reference, [](Backend&) { return make_reference_thin_film(); });
  }

  void check(TableRequest& t, const FieldName& name) const override {
    const bool ior = t.find("base_ior") != nullptr, f0 = t.find("base_f0") != nullptr;
    if (ior == f0)
      throw FieldError(ior ? "base_f0" : "base_ior", "give exactly one of " + name("base_ior") +
                                                         " (a dielectric base) and " + name("base_f0") +
                                                         " (a metal's F0)");
    if (t.number("thickness_max") < t.number("thickness_min"))
      throw FieldError("thickness_max", "must be at least " + name("thickness_min") + " (got " +
                                            fmt_number(t.number("thickness_max")) + " < " +
                                            fmt_number(t.number("thickness_min")) + ")");
    const bool one = t.number("thickness_max") == t.number("thickness_min");
    if (!t.find("height")) t.set("height", one ? 1.0 : t.number("size"));
    if (one && t.number("height") != 1)
      throw FieldError("height",
                       "must be 1 when " + name("thickness_min") + " = " + name("thickness_max") + " (one thickness)");
  }

  std::string default_output(const TableRequest& t) const override {
    std::string stem = "thin_film_ior" + name_number(t.number("film_ior"));
    if (t.find("base_ior")) stem += "_base_ior" + name_number(t.number("base_ior"));
    if (const ParamValue* v = t.find("base_f0")) stem += "_base_f0_" + name_part(*v);
    stem += "_" + name_number(t.number("thickness_min"));
    if (t.number("thickness_max") != t.number("thickness_min")) stem += "-" + name_number(t.number("thickness_max"));
    return stem + "nm" + (t.format.empty() ? ".exr" : output_extension(t));
  }
  OutputFormats formats(const TableRequest&) const override { return table_formats(); }

  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs&, const BakeProgress&) const override {
    const ThinFilmSpec spec = spec_of(t);
    ThinFilmTiming timing;
    BakeResult r;
    Table table = bake_thin_film(backend, spec, &timing);
    if (backend.is_reference()) {
      r.error_bound = 0.0;
      r.error_bound_definition = "the scalar double reference itself (stored as float32)";
    } else {
      const Table ref = bake_thin_film_reference(spec);
      double worst = 0.0;
      for (size_t k = 0; k < table.data.size(); ++k)
        worst = std::max(worst, std::fabs(double(table.data[k]) - double(ref.data[k])));
      r.error_bound = worst;
      r.error_bound_definition =
          "max |table - scalar double reference| over every cell and channel, measured when the table was baked";
    }
    table.set_meta("error_bound", fmt_number(*r.error_bound, "%.3g"));
    table.set_meta("error_bound_definition", r.error_bound_definition);
    if (const std::string above = reflectance_above_one(table); !above.empty()) {
      table.set_meta("reflectance_above_1", above);
      r.warnings.push_back("thin-film: " + above);
    }
    r.device_seconds = timing.device_seconds;
    r.summary = "thin film on " + (spec.base_ior ? "ior " + name_number(*spec.base_ior) : std::string("an F0 base")) +
                " " + std::to_string(table.width) + "x" + std::to_string(table.height) + ", " +
                table.meta("precision") + ", max |table - reference| " + fmt_number(*r.error_bound, "%.2g") + ", " +
                fmt_number(timing.wall_seconds, "%.3f") + " s";
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
  static ThinFilmSpec spec_of(const TableRequest& t) { return thin_film_schema().fill(t); }
};

}  // namespace

const Family& thin_film_family() {
  static const ThinFilmFamily f;
  return f;
}

}  // namespace brdfbake::detail
