// The irradiance family (kind irradiance): diffuse irradiance of the environment as spherical
// harmonics (JSON) and as an irradiance cube. Its descriptor: the schema bound to IrradianceSpec,
// the rules across fields (an engine target's window), names, the bake, the SH JSON and cube
// writes, and the registration of its kernels. Model: model.cpp, sh.cpp, sh_projection.cpp;
// kernels: opencl.cpp (kernels/irradiance.cl), reference.cpp (host/reference/src/irradiance.cpp);
// tests: tests/device/test_irradiance.cpp, tests/reference/test_envmap_reference.cpp.
#include "families/family.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error_figures.hpp"
#include "families/irradiance/kernel.hpp"
#include "families/irradiance/model.hpp"
#include "families/kernels.hpp"
#include "families/spec_schema.hpp"
#include "io/atomic_file.hpp"
#include "text.hpp"

namespace brdfbake::detail {

namespace {

bool is_json(const TableRequest& t) { return output_extension(t) == ".json"; }

// The SH JSON, with the coefficients in the target engine's own convention added where one is named
// (the same numbers bake --target writes into the engine's files).
std::string sh_json_for(const ShCoefficients& sh, const Metadata& meta, const std::string& target_name) {
  const std::string text = sh_to_json(sh, meta);
  const EngineTarget target = engine_target_from_name(target_name);
  if (target == EngineTarget::Generic) return text;
  const EngineSettings e = engine_settings(target);
  std::array<Rgb3, 9> c{};
  const char* layout = "";
  switch (target) {
    case EngineTarget::Filament:
      c = filament_sh(sh);
      layout = "9 RGB, Filament's pre-scaled order (the KTX1 sh key, IndirectLight::irradiance)";
      break;
    case EngineTarget::Babylon:
      c = babylon_polynomial(sh);
      layout = "9 RGB, Babylon's spherical polynomial x, y, z, xx, yy, zz, yz, zx, xy";
      break;
    default:
      c = gltf_irradiance_coefficients(sh);
      layout = "9 RGB, EXT_lights_image_based irradianceCoefficients (l00, l1-1, l10, l11, l2-2, l2-1, l20, l21, l22)";
      break;
  }
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(text);
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (const Rgb3& v : c) a.push_back({v[0], v[1], v[2]});
  j["engine"] = {{"target", target_name},
                 {"engine", e.engine},
                 {"convention", e.sh_description},
                 {"layout", layout},
                 {"coefficients", a}};
  return j.dump(2) + "\n";
}

Metadata sh_metadata(const BakeResult& r) {
  Metadata m;
  for (const auto& [k, v] : r.details)
    if (k == "source" || k == "source_size" || k == "sanitized" || k == "sh_irradiance_error" ||
        k == "sh_irradiance_error_definition" || k == "sh_projection_error" || k == "sh_projection_error_definition")
      m.push_back({k, v});
  // the file's error figure under its kind's name (brdfbake/error_figures.hpp): the SH's, always
  // measured (sh_irradiance_error, rounded up)
  const ErrorFigure& figure = error_figure(TableKind::Irradiance);
  std::string value = "not measured";
  for (const auto& [k, v] : r.details)
    if (k == "sh_irradiance_error") value = v;
  m.push_back({"error_name", figure.name});
  m.push_back({figure.name, value});
  m.push_back({"error_definition", figure.definition});
  return m;
}

// The schema, bound to IrradianceSpec.
SpecSchema<IrradianceSpec> make_irradiance_schema() {
  static const IrradianceSpec d;
  using T = ParamType;
  using S = IrradianceSpec;
  SpecSchema<IrradianceSpec> s;
  s.bind(&S::sh_order, "sh_order",
         ParamDef("sh_order", T::Int, "SH bands: 3 (9 coefficients) or 5 (25)")
             .range(3, 5)
             .def(double(d.sh_order))
             .alias("sh"))
      .bind(&S::window, "window",
            ParamDef("sh_window", T::Name, "windowing of the SH bands against ringing")
                .one_of(enum_names(kShWindowNames))
                .def(std::string(sh_window_name(d.window))),
            by_name(sh_window_from_name))
      // no irradiance_size: SH alone (a .json output), not the struct's default
      .bind("cube_size",
            ParamDef("irradiance_size", T::Int, "face size of the irradiance cube (a cube output only)")
                .range(1, kIrradianceMaxCube)
                .alias("cube_size")
                .alias("cube")
                .defaults_to(fmt_number(d.cube_size) + " for a cube output"),
            [](IrradianceSpec& i, const TableRequest& t) {
              i.cube_size = static_cast<int>(t.number("irradiance_size", 0));
            })
      .bind(&S::source_size, "source_size",
            ParamDef("source_size", T::Int, "face size the environment is converted to first")
                .range(1, kIrradianceMaxSource)
                .def(double(d.source_size)))
      .param(ParamDef("sh_json", T::Path, "a cube output: also write the SH coefficients to this JSON file").output())
      .param(ParamDef("target", T::Name,
                      "an engine's SH conventions (docs/ENGINES.md): its window unless given, and its coefficients "
                      "added to the JSON")
                 .one_of(engine_target_names())
                 .def(std::string("generic")))
      .common("precision", "precision", [](IrradianceSpec& i, const TableRequest& t) { i.precision = t.precision; });
  std::vector<ParamDef> output;
  add_cube_output_params(output);
  return s.params(output);
}

const SpecSchema<IrradianceSpec>& irradiance_schema() {
  static const SpecSchema<IrradianceSpec> s = make_irradiance_schema();
  return s;
}

class IrradianceFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override { return {TableKind::Irradiance}; }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    // RGBA float texels (16 bytes): the source cube on the host and the device; the irradiance cube
    // on the device, the host and in the writer's encoding.
    const double source = t.number("source_size"), cube = t.number("irradiance_size", 0);
    return static_cast<std::uint64_t>(16 * (2 * 6 * source * source + 3 * 6 * cube * cube)) + (std::uint64_t(1) << 20);
  }
  std::string command() const override { return "irradiance"; }
  TableExample example(TableKind) const override {
    TableExample e;
    e.request.environment = "builtin:sun";
    e.request.params = {{"irradiance_size", 4.0}, {"source_size", 8.0}};
    return e;
  }
  CommandText command_text() const override {
    return {"diffuse irradiance of an environment: spherical harmonics and a cube",
            "Diffuse irradiance of an environment: spherical harmonics (.json) and an irradiance cube",
            "brdfbake irradiance --env studio.hdr --sh 3 -o studio_sh.json"};
  }
  std::string summary(TableKind) const override {
    return "diffuse irradiance of an environment: spherical harmonics (.json) and an irradiance cube";
  }
  bool uses_environment() const override { return true; }
  bool needs_device(const TableRequest& t) const override { return t.find("irradiance_size") != nullptr; }

  const std::vector<ParamDef>& schema(TableKind) const override { return irradiance_schema().schema(); }
  std::vector<SpecField> spec_fields(TableKind) const override { return irradiance_schema().fields(); }
  void register_kernels(KernelRegistry& r) const override {
    r.add<IrradianceKernel>(Platform::OpenCl, [](Backend& b) { return make_opencl_irradiance(b); });
    r.add<IrradianceKernel>(Platform::Reference, [](Backend&) { return make_reference_irradiance(); });
  }

  void check(TableRequest& t, const FieldName& name) const override {
    if (t.text("target") != "generic" && !t.was_given("sh_window"))
      t.set("sh_window",
            std::string(sh_window_name(engine_settings(engine_target_from_name(t.text("target"))).sh_window)));
    if (t.number("sh_order") != 3 && t.number("sh_order") != 5)
      throw FieldError("sh_order", "must be 3 or 5 (got " + fmt_number(t.number("sh_order")) + ")");
    const bool json = !t.output.empty()   ? is_json(t)
                      : !t.format.empty() ? t.format == "json"
                                          : !t.find("irradiance_size");
    if (json && t.find("irradiance_size"))
      throw FieldError(
          "irradiance_size",
          "a .json output holds the SH coefficients only: write the cube to .ktx2, .ktx, .dds or a folder");
    if (json && t.find("sh_json"))
      throw FieldError("sh_json", "is for a cube output (the output already is the SH JSON)");
    if (!json && !t.find("irradiance_size")) t.set("irradiance_size", double(IrradianceSpec{}.cube_size));
    (void)name;
  }

  std::string default_output(const TableRequest& t) const override {
    std::string stem = "irradiance_sh" + fmt_number(t.number("sh_order"), "%.0f");
    if (!t.find("irradiance_size") || t.format == "json") return stem + ".json";
    return stem + "_cube" + fmt_number(t.number("irradiance_size"), "%.0f") +
           (t.format.empty() ? ".ktx2" : output_extension(t));
  }
  OutputFormats formats(const TableRequest&) const override {
    OutputFormats f = cube_formats();
    f.extensions.insert(f.extensions.begin(), ".json");
    f.description = "SH coefficients (.json) or " + f.description;
    return f;
  }
  void check_output(const TableRequest& t, const FieldName& name) const override {
    Family::check_output(t, name);
    if (!is_json(t))
      check_cube_output(t, name);
    else if (!t.format.empty() && t.format != "json")
      throw FieldError("format", "'" + t.format + "' does not match the extension of '" + t.output + "'");
  }

  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs& in,
                  const BakeProgress& progress) const override {
    const IrradianceSpec spec = irradiance_schema().fill(t);
    BakeResult r;
    EnvImage scaled;
    double scale = 1.0;
    const EnvImage& env = headroom_environment(*in.environment, scaled, &scale);
    IrradianceResult res = compute_irradiance(backend, env, spec, progress);
    // SH: scaled back in double (finite for any finite radiance: at most 4 pi 3.4e38 x 0.9); the
    // cube's E / pi is at most the largest radiance, a float.
    for (double& v : res.sh.radiance) v *= scale;
    for (double& v : res.sh.irradiance_over_pi) v *= scale;
    if (scale != 1.0 && !res.cube.levels.empty()) {
      for (float& v : res.cube.levels[0]) v = static_cast<float>(double(v) * scale);
      std::string coeffs;
      for (double v : res.sh.irradiance_over_pi) coeffs += (coeffs.empty() ? "" : ",") + fmt_number(v);
      res.cube.set_meta("sh_irradiance_over_pi", coeffs);
    }
    const std::string note = sanitize_note(*in.environment);
    if (!note.empty() && !res.cube.levels.empty()) res.cube.set_meta("sanitized", note);
    // The SH's own error, measured against the exact irradiance of the map (sh_error.cpp): the file's
    // bound when the output is the SH; beside it (details) when it is the cube, whose own error is not
    // measured.
    const ShErrorMeasure sh_error = sh_irradiance_error(env, res.sh);
    const std::string sh_error_definition = "relative RMS of the SH's E / pi (order " + std::to_string(res.sh.order) +
                                            ", window " + sh_window_name(res.sh.window) +
                                            ") against the exact irradiance of the source's pixels, luminance over " +
                                            std::to_string(sh_error.directions) + " directions";
    r.details.push_back({"sh_irradiance_error", bound_text(sh_error.relative_rms)});
    r.details.push_back({"sh_irradiance_error_definition", sh_error_definition});
    // ... and the projection against the converged projection of the same pixels (sh_error.cpp)
    const ShProjectionMeasure projection = sh_projection_error(env, res.sh);
    r.details.push_back({"sh_projection_error", bound_text(projection.relative_rms)});
    r.details.push_back(
        {"sh_projection_error_definition",
         projection.subdivision == 0
             ? std::string("0: the source's cells are integrated exactly (Gauss-Legendre in latitude, closed form in "
                           "longitude; sh_projection.cpp), rounding only")
             : "relative RMS of the luminance of the radiance coefficients (projected at texel centres with exact "
               "solid "
               "angles) against the projection of every texel split " +
                   std::to_string(projection.subdivision) + "x" + std::to_string(projection.subdivision) +
                   " (each sub-texel at its centre with its exact solid angle)"});
    if (spec.cube_size > 0) {
      r.error_bound_definition = "not measured when baked (the irradiance cube; its SH's error is sh_irradiance_error)";
    } else {
      r.error_bound = sh_error.relative_rms;
      r.error_bound_definition = sh_error_definition;
    }
    r.details.push_back({"sh_coefficients", std::to_string(res.sh.order * res.sh.order)});
    r.details.push_back({"source", in.environment->source});
    r.details.push_back({"source_size", fmt_number(spec.source_size, "%.0f")});
    if (!note.empty()) r.details.push_back({"sanitized", note});
    r.device_seconds = res.device_seconds;
    r.summary = "SH order " + std::to_string(res.sh.order) + " (" + std::to_string(res.sh.order * res.sh.order) +
                " coefficients, window " + sh_window_name(res.sh.window) + ")" +
                (spec.cube_size > 0 ? ", irradiance cube " + std::to_string(spec.cube_size) + "^2 (E / pi)" : "") +
                ", device " + fmt_number(res.device_seconds, "%.3f") + " s";
    r.artifact = std::move(res);
    return r;
  }

  WriteReport write(const BakeResult& r, const TableRequest& t, const std::string& path) const override {
    const IrradianceResult& res = *r.irradiance();
    WriteReport w;
    if (is_json(t)) {
      io::write_file_atomically(path, sh_json_for(res.sh, sh_metadata(r), t.text("target")));
      w.encoding = "decimal text (JSON)";
      return w;
    }
    // The cube and, with sh_json, the coefficients: the JSON is staged first and renamed only once
    // the cube is written, so a failure leaves an existing JSON file as it was.
    std::optional<io::TempFile> json;
    if (t.find("sh_json")) {
      json.emplace(t.text("sh_json"));
      io::write_bytes(*json, sh_json_for(res.sh, sh_metadata(r), t.text("target")));
    }
    w = write_cube_result(res.cube, t, path, "irradiance", std::nullopt);
    if (json) json->commit();
    return w;
  }
};

}  // namespace

const Family& irradiance_family() {
  static const IrradianceFamily f;
  return f;
}

}  // namespace brdfbake::detail
