// brdfbake fresnel --model M [parameters] [--size N] [--table 1d|2d] [--vs exact] -o FILE
// brdfbake fresnel --list-materials | --compare --material NAME | --fit (--material NAME | --n --k | --ior)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/fresnel.hpp"
#include "brdfbake/io.hpp"
#include "cli_common.hpp"

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

std::pair<double, double> range_option(const cxxopts::ParseResult& r) {
  const std::string text = r["range"].as<std::string>();
  const auto comma = text.find(',');
  char* e1 = nullptr;
  char* e2 = nullptr;
  const std::string lo = text.substr(0, comma), hi = comma == std::string::npos ? "" : text.substr(comma + 1);
  const double a = std::strtod(lo.c_str(), &e1), b = std::strtod(hi.c_str(), &e2);
  if (comma == std::string::npos || lo.empty() || hi.empty() || *e1 != '\0' || *e2 != '\0' ||
      !std::isfinite(a) || !std::isfinite(b))
    throw UsageError("--range must be two finite numbers LO,HI (got '" + text + "')");
  return {a, b};
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
std::string triple(const Rgb& c, std::string (*f)(double) = f3) {
  return f(c.r) + " " + f(c.g) + " " + f(c.b);
}
std::string pad(std::string s, size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

// The options of table mode that name model parameters, in the spec.
void read_parameters(const cxxopts::ParseResult& r, FresnelSpec& s) {
  if (r.count("material")) s.material = r["material"].as<std::string>();
  if (r.count("f0")) s.f0 = rgb_option(r, "f0");
  if (r.count("f90")) s.f90 = rgb_option(r, "f90");
  if (r.count("f82")) s.f82_tint = rgb_option(r, "f82");
  if (r.count("base-color")) s.base_color = rgb_option(r, "base-color");
  if (r.count("metallic")) s.metallic = finite_number(r, "metallic");
  if (r.count("dielectric-f0")) s.dielectric_f0 = finite_number(r, "dielectric-f0");
  if (r.count("ior")) s.ior = rgb_option(r, "ior");
  if (r.count("ior-outside")) s.ior_outside = finite_number(r, "ior-outside");
  if (r.count("n")) s.n = rgb_option(r, "n");
  if (r.count("k")) s.k = rgb_option(r, "k");
  if (r.count("bias")) s.bias = finite_number(r, "bias");
  if (r.count("scale")) s.scale = finite_number(r, "scale");
  if (r.count("power")) s.power = finite_number(r, "power");
}

// Options other than `allowed` that were given: a mode that does not use them rejects them.
void reject_others(const cxxopts::ParseResult& r, const std::vector<std::string>& allowed,
                   const std::string& mode) {
  for (const auto& kv : r.arguments()) {
    const std::string& key = kv.key();
    bool ok = false;
    for (const std::string& a : allowed) ok = ok || a == key;
    if (!ok) throw UsageError("--" + key + " does not apply to " + mode);
  }
}

int list_materials() {
  const Rgb& wl = kPresetWavelengthsNm;
  std::cout << "Material presets: complex index n + ik at R " << wl.r << " nm, G " << wl.g << " nm, B "
            << wl.b << " nm; F0 = reflectance at normal incidence from air, linear.\n"
            << "'hard-coded' are F0 colours that shaders commonly use for the material, with the\n"
            << "difference hard-coded - exact per channel.\n\n";
  std::cout << pad("name", 14) << pad("kind", 11) << pad("exact F0 (r g b)", 20) << pad("hard-coded F0", 20)
            << pad("difference", 23) << "source of the hard-coded F0\n";
  for (const MaterialPreset& p : material_presets()) {
    const Rgb f0 = exact_f0(p);
    const std::string head = pad(p.name, 14) +
                             pad(p.kind == MaterialKind::Conductor ? "conductor" : "dielectric", 11) +
                             pad(triple(f0), 20);
    const std::vector<HardCodedF0> hard = hard_coded_f0(p);
    if (hard.empty()) std::cout << head << "(none published)\n";
    for (size_t i = 0; i < hard.size(); ++i) {
      const Rgb d{hard[i].f0.r - f0.r, hard[i].f0.g - f0.g, hard[i].f0.b - f0.b};
      std::cout << (i == 0 ? head : std::string(45, ' ')) << pad(triple(hard[i].f0), 20)
                << pad(triple(d, signed3), 23) << hard[i].source << "\n";
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
    std::cout << pad(fresnel_model_name(row.model), 18) << pad(triple(row.max_abs, [](double v) {
                   char b[32];
                   std::snprintf(b, sizeof b, "%.4f", v);
                   return std::string(b);
                 }), 21)
              << pad(triple(row.mean_abs, [](double v) {
                   char b[32];
                   std::snprintf(b, sizeof b, "%.4f", v);
                   return std::string(b);
                 }), 21)
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
            << "  (max |approximation - exact| over " << kFresnelErrorGrid
            << " cosines in [0, 1])\n";
  return 0;
}

}  // namespace

int cmd_fresnel(int argc, char** argv) {
  cxxopts::Options options("brdfbake fresnel", "Bake a Fresnel reflectance table, or compare the models");
  options.add_options()
      ("model", "schlick | schlick-metallic | schlick-ior | dielectric | conductor | f82-tint | empirical", cxxopts::value<std::string>())
      ("material", "a preset (--list-materials)", cxxopts::value<std::string>())
      ("f0", "schlick, f82-tint: F0, v or r,g,b", cxxopts::value<std::string>())
      ("f90", "schlick: F90 (default 1)", cxxopts::value<std::string>())
      ("f82", "f82-tint: the F82 tint, v or r,g,b", cxxopts::value<std::string>())
      ("base-color", "schlick-metallic: base colour r,g,b", cxxopts::value<std::string>())
      ("metallic", "schlick-metallic: metallic in [0, 1]", cxxopts::value<std::string>())
      ("dielectric-f0", "schlick-metallic: the dielectric F0 (default 0.04)", cxxopts::value<std::string>())
      ("ior", "schlick-ior, dielectric: index of the far side, v or r,g,b", cxxopts::value<std::string>())
      ("ior-outside", "schlick-ior, dielectric: index of the side the light comes from (default 1)", cxxopts::value<std::string>())
      ("n", "conductor: real part of the index, r,g,b", cxxopts::value<std::string>())
      ("k", "conductor: extinction coefficient, r,g,b", cxxopts::value<std::string>())
      ("bias", "empirical: bias", cxxopts::value<std::string>())
      ("scale", "empirical: scale", cxxopts::value<std::string>())
      ("power", "empirical: power", cxxopts::value<std::string>())
      ("size", "cells along cos_theta", cxxopts::value<std::string>()->default_value("256"))
      ("endpoints", "cos_theta = i / (N - 1), so that 0 and 1 are cells (default: cell centres (i + 0.5) / N)")
      ("table", "1d (cos_theta; r, g, b) or 2d (cos_theta x f0 or ior; one channel)", cxxopts::value<std::string>()->default_value("1d"))
      ("height", "2d: cells along the y axis (default: --size)", cxxopts::value<std::string>())
      ("range", "2d: the y range LO,HI (default 0,1 for f0 and 1,3 for ior)", cxxopts::value<std::string>())
      ("vs", "exact: add err_r,err_g,err_b = value - exact model for the same material", cxxopts::value<std::string>())
      ("list-materials", "list the material presets with their exact and hard-coded F0")
      ("compare", "every model's error against the exact one for --material, and its device rate")
      ("rate-cells", "--compare: cells of the table the rates are measured on (default 1048576)", cxxopts::value<std::string>())
      ("fit", "Schlick F0 and F82 tint of --material, --n/--k or --ior, with the error each leaves");
  add_table_output_options(options);
  add_common_options(options);
  // The issue spells the complex index --n and --k; cxxopts takes long names of two characters or
  // more, so those two are short options (-n, -k) and their double-dash spellings are mapped here.
  std::vector<std::string> args(argv, argv + argc);
  for (std::string& a : args)
    if (a == "--n" || a == "--k" || a.rfind("--n=", 0) == 0 || a.rfind("--k=", 0) == 0)
      a = a.size() > 3 ? "-" + a.substr(2, 1) + a.substr(4) : "-" + a.substr(2);
  std::vector<char*> arg_ptrs;
  for (std::string& a : args) arg_ptrs.push_back(a.data());
  const auto r = parse(options, argc, arg_ptrs.data());
  if (help_or_stray(options, r)) return 0;
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
  FresnelSpec spec;
  spec.model = fresnel_model_from_name(r["model"].as<std::string>());
  read_parameters(r, spec);
  spec.size = integer(r, "size");
  if (spec.size < 1) throw UsageError("--size must be at least 1 (got '" + r["size"].as<std::string>() + "')");
  spec.endpoints = r.count("endpoints") > 0;
  spec.table = fresnel_table_kind_from_name(r["table"].as<std::string>());
  if (r.count("height")) {
    if (spec.table != FresnelTableKind::TwoD) throw UsageError("--height is for --table 2d");
    spec.height = integer(r, "height");
    if (spec.height < 1) throw UsageError("--height must be at least 1 (got '" + r["height"].as<std::string>() + "')");
  }
  if (r.count("range")) {
    if (spec.table != FresnelTableKind::TwoD) throw UsageError("--range is for --table 2d");
    spec.range = range_option(r);
  }
  spec.precision = precision_option(r);
  bool vs_exact = false;
  if (r.count("vs")) {
    const std::string vs = r["vs"].as<std::string>();
    if (vs != "exact") throw UsageError("--vs takes 'exact' (got '" + vs + "')");
    vs_exact = true;
  }

  // Validate everything before any slow work (opening the device, building the program).
  validate_fresnel_spec(spec);
  const TableOutput out = table_output_option(r);
  if (vs_exact && out.format != TableFormat::Csv && out.format != TableFormat::CHeader)
    throw UsageError("--vs exact adds three error columns: write .csv or .h");
  const FresnelSpec exact = vs_exact ? exact_fresnel_spec(spec) : FresnelSpec{};
  const std::string device_name = device_option(r);
  FresnelTiming timing;
  Table table;
  if (device_name == "reference") {
    table = bake_fresnel_reference(spec, &timing);
  } else {
    Device device = Device::open(device_name);
    table = bake_fresnel(device, spec, &timing);
  }
  if (vs_exact) table = with_error_columns(table, bake_fresnel_reference(exact));
  write_table_output(table, out);
  if (!quiet_option(r)) {
    std::fprintf(stderr, "%s: %s%s%s %dx%d, %s, %.3f s (device %.3f ms)", out.path == "-" ? "stdout" : out.path.c_str(),
                 table.meta("model").c_str(), spec.material.empty() ? "" : " ", spec.material.c_str(), table.width,
                 table.height, table.meta("precision").c_str(), timing.wall_seconds, timing.device_seconds * 1e3);
    if (vs_exact) std::fprintf(stderr, ", max |error| vs exact %s", table.meta("error_max_abs").c_str());
    std::fprintf(stderr, "\n");
  }
  return 0;
}

}  // namespace brdfbake::cli
