// Named material presets: measured complex refractive indices at three representative wavelengths,
// each with its dataset, beside the F0 colour that shaders commonly hard-code for the material.
// Product data (host/src/material_presets.cpp), used by the Fresnel tables (brdfbake/fresnel.hpp);
// tests/host/test_material_presets.cpp checks them against the exact Fresnel reference.
//
// Wavelengths: R = 630 nm, G = 532 nm, B = 465 nm (kPresetWavelengthsNm). Tabulated datasets are
// interpolated linearly in wavelength between their two nearest samples; datasets published as a
// dispersion formula (Sellmeier, Cauchy) are evaluated at the wavelength. Indices are relative to
// vacuum (air differs by 3e-4, below the datasets' precision). Dielectrics carry k = 0: their
// extinction in the visible (water ~1e-9, N-BK7 ~1e-8) changes no reflectance digit.
// An RGB triple of single-wavelength values is the usual real-time convention, not a spectral
// integration against colour-matching functions: it will not reproduce a table of F0 colours that
// was made that way (e.g. Real-Time Rendering's) to the last digit; material_presets.cpp lists both.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "brdfbake/math/types.hpp"

namespace brdfbake {

inline constexpr Rgb kPresetWavelengthsNm{630.0, 532.0, 465.0};

enum class MaterialKind { Conductor, Dielectric };

struct MaterialPreset {
  std::string name;  // lowercase identifier, e.g. "gold", "fused_silica"
  MaterialKind kind;
  Rgb n;                         // real part of the index at kPresetWavelengthsNm
  Rgb k;                         // extinction coefficient (0 for dielectrics)
  std::string nk_source;         // author(s), year, journal reference of the dataset, where it was read
  std::optional<Rgb> common_f0;  // the F0 commonly hard-coded in shaders, if one is published
  std::string common_f0_source;  // where that F0 comes from ("" when common_f0 is empty)
};

// Every preset, in a fixed order: conductors, then dielectrics.
const std::vector<MaterialPreset>& material_presets();

// The preset with exactly this name, or nullptr.
const MaterialPreset* find_material_preset(const std::string& name);

// The exact normal-incidence reflectance from the preset's n, k (from air/vacuum), per channel
// ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2) (Born & Wolf 14.2 at normal incidence).
Rgb exact_f0(const MaterialPreset& preset);

}  // namespace brdfbake
