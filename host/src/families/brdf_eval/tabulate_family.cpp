// The tabulate family (kind tabulate): a BRDF model tabulated as a MERL binary, a grid over
// (theta_i, theta_o, phi_d), directional albedo over theta_o, or a (theta_h, theta_d) slice image,
// by the BRDF evaluation engine's kernel (kernel.hpp, registered by eval_family.cpp). Engine:
// tabulate.cpp and host/src/io/merl.cpp; reference: reference.cpp (host/reference/src/brdf_eval.cpp,
// brdf_albedo.cpp); tests: tests/device/test_brdf_eval.cpp, tests/host/test_merl.cpp.
#include "brdfbake/brdf.hpp"
#include "families/brdf_eval/model.hpp"
#include "families/family.hpp"
#include "families/spec_schema.hpp"

namespace brdfbake::detail {
namespace {

// The example request's material: one in memory (read_materials takes JSON text).
constexpr const char* kExampleMaterial =
    R"({"materials": [{"name": "velvet", "model": "gltf-correlated", "baseColor": [0.3, 0.05, 0.1], "roughness": 0.8, "sheenColor": [0.9, 0.3, 0.4], "sheenRoughness": 0.5}]})";

std::vector<std::string> model_names() {
  std::vector<std::string> v;
  for (BrdfModel m : brdf_models()) v.push_back(brdf_model_name(m));
  return v;
}

bool is_merl(const TableRequest& t) { return t.text("layout") == "merl"; }

// The schema, bound to TabulateSpec; the materials and model are read by spec_of (the file, the
// name and the model's rules across them).
SpecSchema<TabulateSpec> make_tabulate_schema() {
  using T = ParamType;
  using S = TabulateSpec;
  SpecSchema<TabulateSpec> s;
  s.bind("materials", ParamDef("material", T::Path, "material file: our JSON, or a .gltf").needed(), {})
      .param(ParamDef(
          "name", T::Name,
          "the material to use (albedo: default every material; the others: needed when the file holds several)"))
      .bind("model",
            ParamDef("model", T::Name, "the BRDF model").one_of(model_names()).defaults_to("the material's own"), {})
      .bind(&S::layout, "layout",
            ParamDef("layout", T::Name,
                     "merl (90x90x180 MERL binary) | grid (theta_i x theta_o x phi_d) | albedo (over theta_o) | slice "
                     "(theta_h x theta_d image)")
                .one_of(enum_names(kTableLayoutNames))
                .needed(),
            by_name(table_layout_from_name))
      .bind("res",
            ParamDef(
                "res", T::IntList,
                "grid: N or NI,NO,NP (default 32); albedo: N (default 90); slice: N or W,H (default 256); not for merl")
                .range(1, 4096),
            [](TabulateSpec& spec, const TableRequest& t) {
              for (double v : t.numbers("res")) spec.res.push_back(static_cast<int>(v));
            })
      .bind(
          &S::slice_phi_d, "slice_phi_d",
          ParamDef("phi_d", T::Number, "slice: phi_d in radians").range(0, 3.14159265358979323846).defaults_to("pi/2"))
      .bind("options",
            ParamDef("fast_math", T::Flag, "build the kernels with -cl-fast-relaxed-math (opt-in)").def(false),
            [](TabulateSpec& spec, const TableRequest& t) {
              spec.options.precision = t.precision;
              spec.options.fast_math = t.flag("fast_math");
            });
  std::vector<ParamDef> output;
  add_table_output_params(output);
  return s.params(output);
}

const SpecSchema<TabulateSpec>& tabulate_schema() {
  static const SpecSchema<TabulateSpec> s = make_tabulate_schema();
  return s;
}

class TabulateFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override { return {TableKind::Tabulate}; }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    // Every cell is evaluated at a direction pair (6 doubles) to 3 doubles, then stored as floats;
    // the albedo layout integrates each cell over a hemisphere of pairs, in batches.
    const std::string layout = t.text("layout");
    const std::vector<double> res = t.numbers("res");
    double cells = 0;
    if (layout == "merl")
      cells = 90.0 * 90.0 * 180.0;
    else if (layout == "grid")
      cells = res.empty() ? 32.0 * 32 * 32 : res.size() == 1 ? res[0] * res[0] * res[0] : res[0] * res[1] * res[2];
    else if (layout == "albedo")
      cells = (res.empty() ? 90.0 : res[0]) * 4096.0;
    else
      cells = res.empty() ? 256.0 * 256 : res.size() == 1 ? res[0] * res[0] : res[0] * res[1];
    return static_cast<std::uint64_t>(cells * (6 + 3) * 8) + grid_bytes(cells, 3);
  }
  std::string command() const override { return "tabulate"; }
  TableExample example(TableKind) const override {
    TableExample e;
    e.request.params = {{"material", std::string(kExampleMaterial)}, {"layout", std::string("albedo")}, {"res", 4.0}};
    return e;
  }
  CommandText command_text() const override {
    return {"tabulate a BRDF model: MERL binary, grid, directional albedo, slice image",
            "Tabulate a BRDF: MERL binary, grid, directional albedo or a slice image",
            "brdfbake tabulate --material examples/materials.json --name gold --layout merl -o gold.binary"};
  }
  std::string summary(TableKind) const override {
    return "a BRDF tabulated: MERL binary, grid, directional albedo or a slice image";
  }
  std::string default_pixel() const override { return "f32"; }

  const std::vector<ParamDef>& schema(TableKind) const override { return tabulate_schema().schema(); }
  std::vector<SpecField> spec_fields(TableKind) const override { return tabulate_schema().fields(); }

  void check(TableRequest& t, const FieldName& name) const override {
    if (t.find("res") && is_merl(t)) throw FieldError("res", "does not apply to the merl layout (its size is fixed)");
    if (t.find("phi_d") && t.text("layout") != "slice")
      throw FieldError("phi_d", "is for " + name("layout") + " slice");
    try {
      tabulate_resolution(spec_of(t, name));
    } catch (const FieldError&) {
      throw;
    } catch (const Error& e) {
      throw FieldError("", e.what());
    }
  }

  std::string default_output(const TableRequest& t) const override {
    std::string stem = "tabulate_" + t.text("layout");
    if (t.find("model")) stem += "_" + t.text("model");
    if (t.find("name")) stem += "_" + t.text("name");
    if (is_merl(t)) return stem + ".binary";
    return stem + (t.format.empty() ? ".exr" : output_extension(t));
  }
  OutputFormats formats(const TableRequest& t) const override {
    if (is_merl(t)) return {{".binary", ""}, "a MERL binary (.binary, with FILE.json beside it)"};
    return table_formats();
  }
  void check_output(const TableRequest& t, const FieldName& name) const override {
    if (is_merl(t) && (!t.format.empty() || t.output == "-"))
      throw FieldError(t.format.empty() ? "output" : "format",
                       "the merl layout writes a MERL binary file (plus FILE.json): give a file name");
    if (!is_merl(t)) Family::check_output(t, name);
  }

  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs&, const BakeProgress&) const override {
    const TabulateSpec spec = spec_of(t, [](const std::string& f) { return f; });
    const std::vector<int> res = tabulate_resolution(spec);
    TabulateTiming timing;
    BakeResult r;
    if (is_merl(t))
      r.artifact = tabulate_merl(backend, spec, &timing);
    else
      r.artifact = tabulate(backend, spec, &timing);
    r.error_bound_definition =
        "not measured (the kernels' agreement with the reference is in docs/BENCHMARKS.md, "
        "\"Bulk BRDF evaluation\")";
    std::string rs;
    for (int v : res) rs += (rs.empty() ? "" : "x") + std::to_string(v);
    r.device_seconds = timing.device_seconds;
    r.summary = std::string(brdf_model_name(spec.model)) + " " + table_layout_name(spec.layout) + " " + rs + ", " +
                std::to_string(spec.materials.size()) + " material(s), " +
                (backend.is_reference() ? std::string("reference") : std::string(precision_name(t.precision))) + ", " +
                fmt_number(timing.wall_seconds, "%.3f") + " s (device " + fmt_number(timing.device_seconds, "%.3f") +
                " s)";
    return r;
  }

  WriteReport write(const BakeResult& r, const TableRequest& t, const std::string& path) const override {
    if (const MerlTable* m = r.merl()) {
      write_merl(*m, path);
      WriteReport w;
      w.encoding = "float64 (MERL binary)";
      return w;
    }
    return write_table_result(*r.table(), t, path, r.error_bound);
  }
  std::optional<WrittenBytes> write_bytes(const BakeResult& r, const TableRequest& t) const override {
    if (!r.table()) return std::nullopt;  // a MERL file is written
    return table_result_bytes(*r.table(), t, r.error_bound);
  }

 private:
  static TabulateSpec spec_of(const TableRequest& t, const FieldName& name) {
    TabulateSpec s = tabulate_schema().fill(t);
    std::optional<BrdfModel> chosen;
    if (t.find("model")) chosen = brdf_model_from_name(t.text("model"));
    const std::string path = t.text("material");
    std::vector<NamedMaterial> materials;
    try {
      materials = read_materials(path);
    } catch (const Error& e) {
      throw FieldError("material", e.what());
    }
    if (s.layout == TableLayout::Albedo && !t.find("name")) {
      s.materials = materials;
    } else {
      if (!t.find("name") && materials.size() > 1)
        throw FieldError("name", path + " holds " + std::to_string(materials.size()) + " materials; the " +
                                     table_layout_name(s.layout) + " layout tabulates one: choose it with " +
                                     name("name"));
      s.materials = {find_material(materials, t.text("name"), path)};
    }
    s.model = resolve_model(chosen, s.materials.front());
    for (const NamedMaterial& m : s.materials)
      if (resolve_model(chosen, m) != s.model)
        throw FieldError("model", "the materials name different models; give " + name("model") + " (or " +
                                      name("name") + " one material)");
    return s;
  }
};

}  // namespace

const Family& tabulate_family() {
  static const TabulateFamily f;
  return f;
}

}  // namespace brdfbake::detail
