// What each Fresnel approximation costs for one material: every model set from the material, its
// error against the material's exact model, and its device rate; and the F0 colours shaders still
// hard-code.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "families/fresnel/model.hpp"

namespace brdfbake {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Per channel, the max and mean |approx - exact| over the 1-D tables' cells, and the worst.
void add_errors(const Table& approx, const Table& exact, FresnelModelReport& row) {
  double max_c[3] = {0, 0, 0}, sum_c[3] = {0, 0, 0}, x_c[3] = {0, 0, 0};
  for (int i = 0; i < approx.width; ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = std::fabs(static_cast<double>(approx.at(i, 0, c)) - static_cast<double>(exact.at(i, 0, c)));
      sum_c[c] += d;
      if (d > max_c[c]) {
        max_c[c] = d;
        x_c[c] = approx.x[static_cast<size_t>(i)];
      }
    }
  const double n = static_cast<double>(approx.width);
  row.max_abs = {max_c[0], max_c[1], max_c[2]};
  row.mean_abs = {sum_c[0] / n, sum_c[1] / n, sum_c[2] / n};
  for (int c = 0; c < 3; ++c)
    if (max_c[c] > row.worst) {
      row.worst = max_c[c];
      row.cos_at_worst = x_c[c];
    }
}

// The device's rate for the model's spec at options.rate_cells cells: the median kernel time of
// options.rate_runs runs after a warm-up.
void measure_rate(Device& device, const FresnelSpec& s, const FresnelCompareOptions& options, FresnelModelReport& row) {
  FresnelSpec rs = s;
  rs.size = options.rate_cells;
  rs.endpoints = false;
  FresnelTiming timing;
  bake_fresnel(device, rs, &timing);  // warm-up: program build, first touch of the buffers
  std::vector<double> times;
  for (int k = 0; k < std::max(1, options.rate_runs); ++k) {
    bake_fresnel(device, rs, &timing);
    times.push_back(timing.device_seconds);
  }
  row.device_seconds = median(times);
  row.cells_per_second = row.device_seconds > 0 ? static_cast<double>(options.rate_cells) / row.device_seconds : 0.0;
}

}  // namespace

FresnelComparison compare_fresnel_models(const std::string& material, Device* device,
                                         const FresnelCompareOptions& options) {
  const MaterialPreset* preset = detail::find_fresnel_preset(material);
  if (options.grid < 2) throw Error("the comparison grid needs at least 2 cosines");
  if (options.rate_cells < 0) throw Error("rate cells must not be negative");
  FresnelComparison out;
  out.material = preset->name;
  out.exact_model = preset->kind == MaterialKind::Conductor ? FresnelModel::Conductor : FresnelModel::Dielectric;
  out.grid = options.grid;
  out.rate_cells = device ? options.rate_cells : 0;
  if (device && options.rate_cells > 0) out.device = device->info().name;

  FresnelSpec exact_spec;
  exact_spec.model = out.exact_model;
  exact_spec.material = preset->name;
  exact_spec.size = options.grid;
  exact_spec.endpoints = true;
  const Table exact = bake_fresnel_reference(exact_spec);
  const Rgb f0 = exact_f0(*preset);

  for (FresnelModel m : fresnel_models()) {
    if (preset->kind == MaterialKind::Conductor && (m == FresnelModel::SchlickIor || m == FresnelModel::Dielectric))
      continue;  // a real index cannot describe a metal
    FresnelSpec s;
    s.model = m;
    s.size = options.grid;
    s.endpoints = true;
    s.precision = options.precision;
    std::string setting;
    if (m == FresnelModel::Empirical) {
      const double mean_f0 = (f0.r + f0.g + f0.b) / 3.0;
      s.bias = options.bias.value_or(mean_f0);
      s.scale = options.scale.value_or(1.0 - mean_f0);
      s.power = options.power.value_or(5.0);
      setting = !options.bias && !options.scale && !options.power
                    ? "bias = mean exact F0, scale = 1 - bias, power = 5 (grey Schlick)"
                    : "";
    } else {
      s.material = preset->name;
    }
    const Table approx = bake_fresnel_reference(s);
    FresnelModelReport row;
    row.model = m;
    row.setting = approx.meta("parameters");
    if (!setting.empty()) row.setting += " (" + setting + ")";
    add_errors(approx, exact, row);
    if (device && options.rate_cells > 0) measure_rate(*device, s, options, row);
    out.rows.push_back(row);
  }
  return out;
}

// Hoffman 2010, SIGGRAPH course "Physically-Based Shading Models in Film and Game Production",
// Table 1 (values from Real-Time Rendering, 3rd ed.): the F0 colours many shaders still hard-code.
// Linear values; water and diamond are grey.
namespace {
struct LegacyF0 {
  const char* material;
  Rgb f0;
};
const LegacyF0 kLegacyF0[] = {
    {"gold", {1.00, 0.71, 0.29}},    {"silver", {0.95, 0.93, 0.88}},    {"copper", {0.95, 0.64, 0.54}},
    {"iron", {0.56, 0.57, 0.58}},    {"aluminium", {0.91, 0.92, 0.92}}, {"water", {0.02, 0.02, 0.02}},
    {"diamond", {0.17, 0.17, 0.17}},
};
constexpr const char* kLegacySource = "Hoffman 2010 SIGGRAPH course notes, Table 1 (from Real-Time Rendering 3rd ed.)";
}  // namespace

std::vector<HardCodedF0> hard_coded_f0(const MaterialPreset& preset) {
  std::vector<HardCodedF0> out;
  if (preset.common_f0) out.push_back({*preset.common_f0, preset.common_f0_source});
  for (const LegacyF0& l : kLegacyF0) {
    if (preset.name != l.material) continue;
    const bool same = preset.common_f0 && preset.common_f0->r == l.f0.r && preset.common_f0->g == l.f0.g &&
                      preset.common_f0->b == l.f0.b;
    if (!same) out.push_back({l.f0, kLegacySource});
  }
  return out;
}

}  // namespace brdfbake
