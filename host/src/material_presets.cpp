// Material preset data. See brdfbake/material_presets.hpp for the wavelengths and the interpolation rule.
//
// Where the numbers were read: every n, k below was computed from the dataset file of the
// refractiveindex.info database (github.com/polyanskiy/refractiveindex.info-database, public
// domain), path given per entry as database/data-nk/<path>, by linear interpolation between the two
// tabulated samples that bracket each wavelength (named per entry) or by evaluating the published
// dispersion formula; rounded to 3 decimals (metals) or 4 (dielectrics), beyond the datasets' own
// precision (Johnson & Christy give n to 0.01).
//
// The hard-coded F0 column comes from Real-Time Rendering, 4th ed. (Akenine-Möller, Haines, Hoffman
// et al. 2018), sec. 9.5.2: Table 9.1 (dielectrics), Table 9.2 (metals), Table 9.3 (diamond), linear
// values; read from the chapter's transcription in github.com/ahuibo/Real-Time-Rendering-4th-CN.
// They come from other measurements and are not point samples at our three wavelengths, so they
// differ from exact_f0() by up to 0.10 (titanium blue: 0.549 from Johnson & Christy 1974 at 465 nm
// against 0.449; iron blue 0.500 against 0.578); the test suite bounds the gap.
// Older values still hard-coded in many shaders, from RTR 3rd ed. as reprinted in Hoffman's SIGGRAPH
// 2010 course notes "Physically-Based Shading Models in Film and Game Production", Table 1:
//   gold (1.00, 0.71, 0.29), silver (0.95, 0.93, 0.88), copper (0.95, 0.64, 0.54),
//   iron (0.56, 0.57, 0.58), aluminium (0.91, 0.92, 0.92), water 0.02, diamond 0.17;
// and e.g. gold (1.000, 0.766, 0.336) as in Unity Shader Graph's Metal Reflectance node.
#include "brdfbake/material_presets.hpp"

namespace brdfbake {
namespace {

constexpr const char* kRtr4Metals = "Real-Time Rendering 4th ed. (2018), Table 9.2, linear sRGB";

// The conductors: complex indices per R, G, B and their F0 for comparison.
std::vector<MaterialPreset> conductor_presets() {
  using K = MaterialKind;
  return {
      // ---- Conductors ----------------------------------------------------------------------
      // main/Au/Johnson.yml; samples 616.8/659.5, 520.9/548.6, 450.9/471.4 nm.
      {"gold",
       K::Conductor,
       {0.188, 0.544, 1.332},
       {3.403, 2.231, 1.869},
       "Johnson & Christy 1972, Phys. Rev. B 6, 4370 (evaporated films, room temperature)",
       Rgb{1.000, 0.782, 0.344},
       kRtr4Metals},
      // main/Ag/Johnson.yml; same samples as gold.
      {"silver",
       K::Conductor,
       {0.057, 0.054, 0.047},
       {4.254, 3.429, 2.803},
       "Johnson & Christy 1972, Phys. Rev. B 6, 4370 (evaporated films, room temperature)",
       Rgb{0.972, 0.960, 0.915},
       kRtr4Metals},
      // main/Cu/Johnson.yml; same samples as gold.
      {"copper",
       K::Conductor,
       {0.275, 1.116, 1.247},
       {3.373, 2.596, 2.456},
       "Johnson & Christy 1972, Phys. Rev. B 6, 4370 (evaporated films, room temperature)",
       Rgb{0.955, 0.638, 0.538},
       kRtr4Metals},
      // main/Al/Rakic.yml; samples 619.9/652.3, 516.6/563.6, 442.8/476.9 nm.
      {"aluminium",
       K::Conductor,
       {1.430, 0.939, 0.686},
       {7.508, 6.420, 5.635},
       "Rakic 1995, Appl. Opt. 34, 4755 (evaporated films, Kramers-Kronig/semiquantum analysis)",
       Rgb{0.913, 0.922, 0.924},
       kRtr4Metals},
      // main/Fe/Johnson.yml; samples 617/659, 521/549, 451/471 nm (also Cr, Ti, Ni below).
      // Johnson & Christy 1974 covers Ti, V, Cr, Mn, Fe, Co, Ni and Pd, not Pt.
      {"iron",
       K::Conductor,
       {2.892, 2.895, 2.646},
       {3.065, 2.918, 2.805},
       "Johnson & Christy 1974, Phys. Rev. B 9, 5056 (films, room temperature)",
       Rgb{0.562, 0.565, 0.578},
       kRtr4Metals},
      // main/Cr/Johnson.yml.
      {"chromium",
       K::Conductor,
       {3.145, 3.034, 2.456},
       {3.312, 3.330, 3.210},
       "Johnson & Christy 1974, Phys. Rev. B 9, 5056 (films, room temperature)",
       Rgb{0.549, 0.556, 0.554},
       kRtr4Metals},
      // main/Ti/Johnson.yml.
      {"titanium",
       K::Conductor,
       {2.698, 2.479, 2.305},
       {3.757, 3.351, 3.082},
       "Johnson & Christy 1974, Phys. Rev. B 9, 5056 (films, room temperature)",
       Rgb{0.542, 0.497, 0.449},
       kRtr4Metals},
      // main/Ni/Johnson.yml.
      {"nickel",
       K::Conductor,
       {1.990, 1.877, 1.765},
       {4.094, 3.495, 3.048},
       "Johnson & Christy 1974, Phys. Rev. B 9, 5056 (films, room temperature)",
       Rgb{0.660, 0.609, 0.526},
       kRtr4Metals},
      // main/Pt/Rakic-LD.yml (tabulated every ~2 nm from the model). Not in Johnson & Christy; the
      // Werner 2009 REELS set (main/Pt/Werner.yml) gives n ~ 0.46 at 620 nm, F0 ~ 0.95, far from
      // every optical measurement, so it is not used.
      {"platinum",
       K::Conductor,
       {2.310, 2.046, 1.887},
       {4.147, 3.602, 3.224},
       "Rakic, Djurisic, Elazar & Majewski 1998, Appl. Opt. 37, 5271 (Lorentz-Drude fit to "
       "measured data)",
       Rgb{0.673, 0.637, 0.585},
       kRtr4Metals},
  };
}

// The dielectrics: real indices per R, G, B (no extinction).
std::vector<MaterialPreset> dielectric_presets() {
  using K = MaterialKind;
  const Rgb zero{0.0, 0.0, 0.0};
  const auto grey = [](double v) { return Rgb{v, v, v}; };
  return {
      // ---- Dielectrics ---------------------------------------------------------------------
      // main/H2O/Daimon-20.0C.yml, 4-term Sellmeier; n_D = 1.3333.
      {"water",
       K::Dielectric,
       {1.3322, 1.3354, 1.3387},
       zero,
       "Daimon & Masumura 2007, Appl. Opt. 46, 3811 (distilled water, 20.0 C, Sellmeier)",
       grey(0.02),
       "Real-Time Rendering 4th ed. (2018), Table 9.1"},
      // main/H2O/Warren-2008.yml; samples 620/630 (R on a sample), 530/540, 460/470 nm.
      {"ice",
       K::Dielectric,
       {1.3085, 1.3116, 1.3148},
       zero,
       "Warren & Brandt 2008, J. Geophys. Res. 113, D14220 (ice at -7 C)",
       std::nullopt,
       ""},
      // glass/schott/N-BK7.yml, 3-term Sellmeier; n_d = 1.5168.
      {"glass",
       K::Dielectric,
       {1.5152, 1.5195, 1.5240},
       zero,
       "SCHOTT N-BK7 borosilicate crown, Sellmeier from the SCHOTT Zemax catalogue 2017-01-20b",
       grey(0.04),
       "Real-Time Rendering 4th ed. (2018), Table 9.1, plastics and glass 0.04-0.05"},
      // main/SiO2/Malitson.yml, 3-term Sellmeier; n_D = 1.4584.
      {"fused_silica",
       K::Dielectric,
       {1.4571, 1.4607, 1.4645},
       zero,
       "Malitson 1965, J. Opt. Soc. Am. 55, 1205 (fused silica, 20 C, Sellmeier)",
       grey(0.04),
       "Real-Time Rendering 4th ed. (2018), Table 9.1, plastics and glass 0.04-0.05"},
      // organic/(C5H8O2)n - poly(methyl methacrylate)/Sultanova.yml, 1-term Sellmeier; n_D = 1.4905.
      {"pmma",
       K::Dielectric,
       {1.4888, 1.4937, 1.4991},
       zero,
       "Sultanova, Kasarova & Nikolov 2009, Acta Phys. Pol. A 116, 585 (PMMA, 20 C)",
       grey(0.04),
       "Real-Time Rendering 4th ed. (2018), Table 9.1, plastics and glass 0.04-0.05"},
      // organic/(C16H14O3)n - polycarbonate/Sultanova.yml, 1-term Sellmeier; n_D = 1.5846.
      {"polycarbonate",
       K::Dielectric,
       {1.5807, 1.5917, 1.6041},
       zero,
       "Sultanova, Kasarova & Nikolov 2009, Acta Phys. Pol. A 116, 585 (polycarbonate, 20 C)",
       grey(0.05),
       "Hoffman 2010 SIGGRAPH course notes, Table 1 (from RTR 3rd ed.), \"plastic high\" 0.05"},
      // main/Al2O3/Malitson-o.yml, 3-term Sellmeier, ordinary ray; n_D = 1.7681.
      {"sapphire",
       K::Dielectric,
       {1.7660, 1.7717, 1.7776},
       zero,
       "Malitson & Dodge 1972, J. Opt. Soc. Am. 62, 1405 (synthetic sapphire, ordinary ray, 20 C)",
       grey(0.08),
       "Hoffman 2010 SIGGRAPH course notes, Table 1 (from RTR 3rd ed.), \"glass (high) / ruby\" "
       "0.08 (ruby is corundum, as sapphire)"},
      // main/C/Peter.yml, 2-term Sellmeier; n_D = 2.4173.
      {"diamond",
       K::Dielectric,
       {2.4125, 2.4260, 2.4410},
       zero,
       "Peter 1923, Z. Phys. 15, 358 (diamond, room temperature, Sellmeier)",
       Rgb{0.171, 0.172, 0.176},
       "Real-Time Rendering 4th ed. (2018), Table 9.3"},
      // Epidermis Cauchy fit n = 1.4134 + 7907.96 nm^2 / lambda^2 - 389.98 nm^4 / lambda^4, as
      // transcribed in the skinoptics package (V. Lima 2024, skinoptics.refractive_index); the same
      // paper's Cornu fit agrees to 1e-3 at all three wavelengths. n_D = 1.4362.
      {"skin",
       K::Dielectric,
       {1.4333, 1.4413, 1.4500},
       zero,
       "Ding, Lu, Wooden, Kragel & Hu 2006, Phys. Med. Biol. 51, 1479 (human epidermis, Cauchy)",
       grey(0.028),
       "Real-Time Rendering 4th ed. (2018), Table 9.1"},
  };
}

std::vector<MaterialPreset> make_presets() {
  std::vector<MaterialPreset> all = conductor_presets();
  for (MaterialPreset& p : dielectric_presets()) all.push_back(std::move(p));
  return all;
}

}  // namespace

const std::vector<MaterialPreset>& material_presets() {
  static const std::vector<MaterialPreset> presets = make_presets();
  return presets;
}

const MaterialPreset* find_material_preset(const std::string& name) {
  for (const MaterialPreset& p : material_presets())
    if (p.name == name) return &p;
  return nullptr;
}

Rgb exact_f0(const MaterialPreset& preset) {
  const auto f0 = [](double n, double k) {
    const double k2 = k * k;
    return ((n - 1.0) * (n - 1.0) + k2) / ((n + 1.0) * (n + 1.0) + k2);
  };
  return {f0(preset.n.r, preset.k.r), f0(preset.n.g, preset.k.g), f0(preset.n.b, preset.k.b)};
}

}  // namespace brdfbake
