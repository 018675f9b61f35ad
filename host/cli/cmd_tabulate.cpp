// brdfbake tabulate --model M --material FILE --layout merl|grid|albedo|slice [--res ...] -o FILE
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/io.hpp"
#include "cli_common.hpp"

namespace brdfbake::cli {
namespace {

// "N" or "N,M[,K]": positive integers.
std::vector<int> parse_res(const std::string& text) {
  std::vector<int> out;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    char* end = nullptr;
    const long v = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || v < 1 || v > 1000000)
      throw UsageError("--res must be positive integers separated by commas (got '" + text + "')");
    out.push_back(static_cast<int>(v));
  }
  if (out.empty()) throw UsageError("--res must be positive integers separated by commas (got '" + text + "')");
  return out;
}

}  // namespace

int cmd_tabulate(int argc, char** argv) {
  cxxopts::Options options("brdfbake tabulate", "Tabulate a BRDF: MERL, grid, directional albedo or a slice image");
  options.add_options()
      ("model", "disney | gltf | gltf-correlated | lambert | phong | blinn-phong | cook-torrance | blinn-phong-from-pbr (default: the material's own)", cxxopts::value<std::string>())
      ("material", "material file: our JSON, or a .gltf", cxxopts::value<std::string>())
      ("name", "the material to use (albedo: default all of them; the others: needed when the file holds several)", cxxopts::value<std::string>()->default_value(""))
      ("layout", "merl (90x90x180 MERL binary) | grid (theta_i x theta_o x phi_d) | albedo (over theta_o) | slice (theta_h x theta_d image)", cxxopts::value<std::string>())
      ("res", "grid: N or NI,NO,NP (default 32); albedo: N (default 90); slice: N or W,H (default 256); not for merl", cxxopts::value<std::string>())
      ("phi-d", "slice: phi_d in radians, in [0, pi] (default pi/2)", cxxopts::value<std::string>())
      ("fast-math", "build the kernels with -cl-fast-relaxed-math")
      ("o,output", "merl: the MERL binary (plus FILE.json); others: .exr .png .hdr .ktx2 .csv .h, or - with --format csv", cxxopts::value<std::string>())
      ("format", "output format when it cannot come from the file name", cxxopts::value<std::string>())
      ("pixel", "f16 | f32 for .ktx2 and .h", cxxopts::value<std::string>()->default_value("f32"));
  add_common_options(options);
  const auto r = parse(options, argc, argv);
  if (help_or_stray(options, r)) return 0;
  if (!r.count("material")) throw UsageError("missing --material FILE");
  if (!r.count("layout")) throw UsageError("missing --layout (merl, grid, albedo or slice)");
  if (!r.count("output")) throw UsageError("missing -o FILE");

  TabulateSpec spec;
  spec.layout = table_layout_from_name(r["layout"].as<std::string>());
  std::optional<BrdfModel> chosen;
  if (r.count("model")) chosen = brdf_model_from_name(r["model"].as<std::string>());
  const std::string material_path = r["material"].as<std::string>();
  const auto materials = read_materials(material_path);
  const std::string name = r["name"].as<std::string>();
  if (spec.layout == TableLayout::Albedo && name.empty()) {
    spec.materials = materials;
  } else {
    if (name.empty() && materials.size() > 1)
      throw UsageError(material_path + " holds " + std::to_string(materials.size()) + " materials; the " +
                       table_layout_name(spec.layout) + " layout tabulates one: choose it with --name");
    spec.materials = {find_material(materials, name, material_path)};
  }
  spec.model = resolve_model(chosen, spec.materials.front());
  for (const NamedMaterial& m : spec.materials)
    if (resolve_model(chosen, m) != spec.model)
      throw UsageError("the materials name different models; give --model (or --name one material)");
  if (r.count("res")) spec.res = parse_res(r["res"].as<std::string>());
  if (r.count("phi-d")) {
    if (spec.layout != TableLayout::Slice) throw UsageError("--phi-d is for --layout slice");
    spec.slice_phi_d = finite_number(r, "phi-d");
  }
  spec.options.precision = precision_from_name(r["precision"].as<std::string>());
  spec.options.fast_math = r.count("fast-math") > 0;
  const std::vector<int> res = tabulate_resolution(spec);  // validates before any slow work

  const std::string out = r["output"].as<std::string>();
  TableFormat format = TableFormat::Csv;
  TableWriteOptions wo;
  if (spec.layout != TableLayout::Merl) {
    if (r.count("format")) {
      format = table_format_from_name(r["format"].as<std::string>());
    } else if (out == "-") {
      throw UsageError("-o - writes to standard output and needs --format csv");
    } else {
      format = table_format_from_path(out);
    }
    if (out == "-" && format != TableFormat::Csv) throw UsageError("only --format csv can go to standard output");
    const std::string pixel = r["pixel"].as<std::string>();
    if (pixel == "f16") wo.pixel = PixelType::F16;
    else if (pixel == "f32") wo.pixel = PixelType::F32;
    else throw UsageError("--pixel must be f16 or f32 (got '" + pixel + "')");
  } else if (out == "-" || r.count("format")) {
    throw UsageError("the merl layout writes a MERL binary file (plus FILE.json); give -o FILE");
  }

  const bool quiet = r.count("quiet") > 0;
  const std::string device_name = r["device"].as<std::string>();
  TabulateTiming timing;
  std::optional<Device> device;
  if (device_name != "reference") device = Device::open(device_name);
  if (spec.layout == TableLayout::Merl) {
    const MerlTable t = device ? tabulate_merl(*device, spec, &timing) : tabulate_merl_reference(spec, &timing);
    write_merl(t, out);
  } else {
    const Table t = device ? tabulate(*device, spec, &timing) : tabulate_reference(spec, &timing);
    if (out == "-") {
      write_table_csv(t, std::cout);
    } else {
      write_table(t, out, format, wo);
    }
  }
  if (!quiet) {
    std::string rs;
    for (int v : res) rs += (rs.empty() ? "" : "x") + std::to_string(v);
    std::fprintf(stderr, "%s: %s %s %s, %zu material(s), %s, %.3f s (device %.3f s)\n", out == "-" ? "stdout" : out.c_str(),
                 brdf_model_name(spec.model), table_layout_name(spec.layout), rs.c_str(), spec.materials.size(),
                 device ? precision_name(spec.options.precision) : "reference", timing.wall_seconds, timing.device_seconds);
  }
  return 0;
}

}  // namespace brdfbake::cli
