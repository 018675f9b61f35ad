// brdfbake fresnel --model M [parameters] [--size N] [--table 1d|2d] [--vs exact] -o FILE
// brdfbake fresnel --list-materials | --compare --material NAME | --fit (--material NAME | --n --k | --ior)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/fresnel.hpp"
#include "brdfbake/io.hpp"
#include "cli_table.hpp"

namespace brdfbake::cli {
namespace {

// "v" (grey) or "r,g,b": every field a finite number, nothing else.
Rgb rgb_option(const cxxopts::ParseResult& r, const std::string& name) {
  const std::string text = r[name].as<std::string>();
  std::vector<double> values;
  std::string field;
  std::istringstream in(text);
  bool ok = !text.empty() && text.back() != ',';
  while (ok && std::getline(in, field, ',')) {
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    ok = !field.empty() && *end == '\0' && std::isfinite(v);
    values.push_back(v);
  }
  if (!ok || (values.size() != 1 && values.size() != 3))
    throw UsageError("--" + name + " must be one finite number or three comma-separated finite numbers r,g,b (got '" +
                     text + "')");
  return values.size() == 1 ? Rgb{values[0], values[0], values[0]} : Rgb{values[0], values[1], values[2]};
}

std::string f3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f", v);
  return b;
}
std::string signed3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%+.3f", v);
  return b;
}
std::string triple(const Rgb& c, std::string (*f)(double) = f3) { return f(c.r) + " " + f(c.g) + " " + f(c.b); }
std::string pad(std::string s, size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

// Options other than `allowed` that were given: a mode that does not use them rejects them.
void reject_others(const cxxopts::ParseResult& r, const std::vector<std::string>& allowed, const std::string& mode) {
  for (const auto& kv : r.arguments()) {
    const std::string& key = kv.key();
    bool ok = false;
    for (const std::string& a : allowed) ok = ok || a == key;
    if (!ok) throw UsageError("--" + key + " does not apply to " + mode);
  }
}

int list_materials() {
  const Rgb& wl = kPresetWavelengthsNm;
  std::cout << "Material presets: complex index n + ik at R " << wl.r << " nm, G " << wl.g << " nm, B " << wl.b
            << " nm; F0 = reflectance at normal incidence from air, linear.\n"
            << "'hard-coded' are F0 colours that shaders commonly use for the material, with the\n"
            << "difference hard-coded - exact per channel.\n\n";
  std::cout << pad("name", 14) << pad("kind", 11) << pad("exact F0 (r g b)", 20) << pad("hard-coded F0", 20)
            << pad("difference", 23) << "source of the hard-coded F0\n";
  for (const MaterialPreset& p : material_presets()) {
    const Rgb f0 = exact_f0(p);
    const std::string head =
        pad(p.name, 14) + pad(p.kind == MaterialKind::Conductor ? "conductor" : "dielectric", 11) + pad(triple(f0), 20);
    const std::vector<HardCodedF0> hard = hard_coded_f0(p);
    if (hard.empty()) std::cout << head << "(none published)\n";
    for (size_t i = 0; i < hard.size(); ++i) {
      const Rgb d{hard[i].f0.r - f0.r, hard[i].f0.g - f0.g, hard[i].f0.b - f0.b};
      std::cout << (i == 0 ? head : std::string(45, ' ')) << pad(triple(hard[i].f0), 20) << pad(triple(d, signed3), 23)
                << hard[i].source << "\n";
    }
  }
  std::cout << "\nSources of n and k:\n";
  for (const MaterialPreset& p : material_presets())
    std::cout << "  " << pad(p.name + ":", 15) << "n = " << triple(p.n) << ", k = " << triple(p.k) << "; "
              << p.nk_source << "\n";
  return 0;
}

int compare(const cxxopts::ParseResult& r) {
  if (!r.count("material")) throw UsageError("--compare needs --material NAME");
  FresnelCompareOptions o;
  o.precision = precision_option(r);
  if (r.count("rate-cells")) {
    o.rate_cells = integer(r, "rate-cells");
    if (o.rate_cells < 1 || o.rate_cells > kFresnelMaxCells)
      throw UsageError("--rate-cells must be between 1 and " + std::to_string(kFresnelMaxCells));
  }
  if (r.count("bias")) o.bias = finite_number(r, "bias");
  if (r.count("scale")) o.scale = finite_number(r, "scale");
  if (r.count("power")) o.power = finite_number(r, "power");
  const std::string material = r["material"].as<std::string>();
  const std::string device_name = device_option(r);
  FresnelComparison c;
  if (device_name == "reference") {
    c = compare_fresnel_models(material, nullptr, o);
  } else {
    FresnelCompareOptions quick = o;
    quick.rate_cells = 0;
    compare_fresnel_models(material, nullptr, quick);  // validates before opening a device
    Device device = Device::open(device_name);
    c = compare_fresnel_models(material, &device, o);
  }
  std::cout << c.material << ": every model against the exact " << fresnel_model_name(c.exact_model)
            << " model, |model - exact| over " << c.grid << " cosines in [0, 1] (both ends), per channel r g b\n";
  if (!c.device.empty())
    std::cout << "rate: RGB cells per second on " << c.device << ", " << precision_name(o.precision) << ", a "
              << c.rate_cells << "-cell table, kernel time by event profiling (median of " << o.rate_runs
              << " after a warm-up)\n";
  std::cout << "\n"
            << pad("model", 18) << pad("max |error|", 21) << pad("mean |error|", 21) << pad("worst at cos", 14)
            << pad("Mcells/s", 10) << "setting\n";
  for (const FresnelModelReport& row : c.rows) {
    char rate[32];
    if (row.cells_per_second > 0)
      std::snprintf(rate, sizeof rate, "%.1f", row.cells_per_second * 1e-6);
    else
      std::snprintf(rate, sizeof rate, "-");
    char worst[32];
    std::snprintf(worst, sizeof worst, "%.4f", row.cos_at_worst);
    std::cout << pad(fresnel_model_name(row.model), 18)
              << pad(triple(row.max_abs,
                            [](double v) {
                              char b[32];
                              std::snprintf(b, sizeof b, "%.4f", v);
                              return std::string(b);
                            }),
                     21)
              << pad(triple(row.mean_abs,
                            [](double v) {
                              char b[32];
                              std::snprintf(b, sizeof b, "%.4f", v);
                              return std::string(b);
                            }),
                     21)
              << pad(row.worst > 0 ? worst : "-", 14) << pad(rate, 10) << row.setting << "\n";
  }
  return 0;
}

int fit(const cxxopts::ParseResult& r) {
  Rgb n, k{0, 0, 0};
  std::string what;
  if (r.count("material")) {
    if (r.count("n") || r.count("k") || r.count("ior") || r.count("ior-outside"))
      throw UsageError("--fit takes either --material or the index (--n --k, or --ior), not both");
    FresnelSpec s;
    s.model = FresnelModel::Conductor;
    s.material = r["material"].as<std::string>();
    validate_fresnel_spec(s);  // the unknown-material message, naming the presets
    const MaterialPreset* p = find_material_preset(s.material);
    if (!p) throw Error("unknown material '" + s.material + "'");
    n = p->n;
    k = p->k;
    what = p->name;
  } else if (r.count("n") || r.count("k")) {
    if (!r.count("n") || !r.count("k")) throw UsageError("--fit with a complex index needs both --n and --k");
    if (r.count("ior")) throw UsageError("--fit takes either --n --k or --ior, not both");
    n = rgb_option(r, "n");
    k = rgb_option(r, "k");
    what = "n + ik";
  } else if (r.count("ior")) {
    const Rgb ior = rgb_option(r, "ior");
    const double outside = r.count("ior-outside") ? finite_number(r, "ior-outside") : 1.0;
    if (!(outside > 0)) throw UsageError("--ior-outside must be positive");
    n = {ior.r / outside, ior.g / outside, ior.b / outside};
    what = "relative index ior / ior-outside";
  } else {
    throw UsageError("--fit needs --material NAME, --n r,g,b --k r,g,b, or --ior N");
  }
  const ConductorFit f = fit_conductor(n, k);
  std::cout << what << ": n = " << triple(n) << ", k = " << triple(k) << " (r g b)\n"
            << "  Schlick F0 (exact at normal incidence):  " << triple(f.f0) << "   max error left "
            << triple(f.schlick_max_error) << "\n"
            << "  F82 tint with that F0 (exact at cos 1/7): " << triple(f.f82_tint) << "   max error left "
            << triple(f.f82_max_error) << "\n"
            << "  (max |approximation - exact| over " << kFresnelErrorGrid << " cosines in [0, 1])\n";
  return 0;
}

}  // namespace

int cmd_fresnel(int argc, char** argv) {
  // The modes beside table mode; their options are the schema's where they share a name
  // (--material, --n, --k, --ior, --ior-outside, --bias, --scale, --power).
  TableCommand c{"fresnel",
                 "Bake a Fresnel reflectance table, or compare the models",
                 "brdfbake fresnel --model conductor --material gold -o gold.exr",
                 {},
                 {},
                 {"list-materials", "compare", "fit", "rate-cells"}};
  c.add_extra = [](cxxopts::Options& options) {
    options.add_options()("list-materials", "list the material presets with their exact and hard-coded F0")(
        "compare", "every model's error against the exact one for --material, and its device rate")(
        "rate-cells", "--compare: cells of the table the rates are measured on (default 1048576)",
        cxxopts::value<std::string>())(
        "fit", "Schlick F0 and F82 tint of --material, --n/--k or --ior, with the error each leaves");
  };
  c.handle_extra = [](const cxxopts::ParseResult& r) -> std::optional<int> {
    const int modes = static_cast<int>(r.count("list-materials") + r.count("compare") + r.count("fit"));
    if (modes > 1) throw UsageError("give one of --list-materials, --compare and --fit");
    if (r.count("list-materials")) {
      reject_others(r, {"list-materials", "quiet"}, "--list-materials");
      return list_materials();
    }
    if (r.count("compare")) {
      reject_others(r, {"compare", "material", "precision", "device", "rate-cells", "bias", "scale", "power", "quiet"},
                    "--compare");
      return compare(r);
    }
    if (r.count("fit")) {
      reject_others(r, {"fit", "material", "n", "k", "ior", "ior-outside", "quiet"}, "--fit");
      return fit(r);
    }
    if (r.count("rate-cells")) throw UsageError("--rate-cells is for --compare");
    if (!r.count("model")) throw UsageError("missing --model (or --list-materials, --compare, --fit)");
    return std::nullopt;
  };
  // "--vs exact" (the original spelling) is the flag --vs-exact.
  std::vector<std::string> args(argv, argv + argc);
  for (size_t i = 0; i < args.size(); ++i)
    if (args[i] == "--vs" || args[i].rfind("--vs=", 0) == 0) {
      std::string v = args[i] == "--vs" ? (i + 1 < args.size() ? args[i + 1] : "") : args[i].substr(5);
      if (v != "exact") throw UsageError("--vs takes 'exact' (got '" + v + "')");
      if (args[i] == "--vs") args.erase(args.begin() + static_cast<long>(i) + 1);
      args[i] = "--vs-exact";
    }
  std::vector<char*> ptrs;
  for (std::string& a : args) ptrs.push_back(a.data());
  return run_table_command(c, static_cast<int>(ptrs.size()), ptrs.data());
}

}  // namespace brdfbake::cli
