// Scalar double-precision reference of the bulk-evaluated BRDF models: the Disney principled BRDF
// (Burley 2012), the glTF 2.0 metallic-roughness BRDF (Appendix B, with KHR_materials_sheen,
// _clearcoat, _specular and _ior), and the classic shading models (Lambert, Phong, Blinn-Phong,
// Cook-Torrance, and the Blinn-Phong imitation of metallic-roughness).
//
// Written from the papers and specification texts, independently of kernels/brdf_eval.cl. Each
// physical term is one small cited function; the models are compositions of them (and of the terms
// of ggx.hpp, charlie.hpp, burley.hpp and fresnel.hpp, reused where they fit).
//
// Conventions (docs/CONVENTIONS.md, "BRDF evaluation"):
//   - f is the BRDF value, without the cosine: outgoing radiance = f * incident irradiance.
//   - wi (towards the light) and wo (towards the viewer) are in tangent space: normal +z, tangent +x
//     (the anisotropy's alpha_x axis), bitangent +y. They need not be unit: they are normalised
//     here; a zero, infinite or NaN vector throws std::invalid_argument.
//   - f = 0 when either direction is at or below the horizon (n.wi <= 0 or n.wo <= 0).
//   - Above it, every cosine with the normal enters the terms floored at kBrdfMinCosine.
//   - roughness is perceptual; GGX and Beckmann widths are alpha = roughness^2 (floored at kMinAlpha
//     except in Disney, which keeps Burley's own floor of 0.001).
//   - Colours are linear RGB, channel by channel.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/types.hpp"
#include "brdfbake/reference/fresnel.hpp"

namespace brdfbake::reference {

// The conventions' floors and ranges (brdfbake/math/conventions.hpp): n.l and n.v above the horizon
// are floored at kBrdfMinCosine, Disney's GGX widths at kDisneyMinAlpha, every other width at
// kMinAlpha; a Phong exponent is at most kMaxShininess.
using math::kBrdfMinCosine;
using math::kDisneyMinAlpha;
using math::kMaxShininess;

// The reference's own parameter types. They mirror the public API's (brdfbake/brdf.hpp: BrdfModel,
// Material) field for field, but are separate types: the oracle states what each model reads
// without depending on the product's headers, and the product's API can grow (or the oracle
// change) without the other following. The product's reference backend converts
// (host/src/families/brdf_eval/reference.cpp).
enum class BrdfModel {
  Disney,             // Burley 2012, in the BRDF Explorer's disney.brdf formulation
  Gltf,               // glTF 2.0 Appendix B, separable Smith G
  GltfCorrelated,     // the same with the height-correlated Smith visibility (Khronos sample renderer)
  Lambert,            // Lambert 1760
  Phong,              // Phong 1975, reciprocal BRDF form
  BlinnPhong,         // Blinn 1977
  CookTorrance,       // Cook & Torrance 1982, Beckmann or GGX
  BlinnPhongFromPbr,  // metallic-roughness mapped to a normalised, Fresnel-weighted Blinn-Phong
};

enum class MicrofacetDistribution { Beckmann, Ggx };

// Every parameter of every model; a model reads only its own (docs/CONVENTIONS.md lists which).
// Ranges are checked by the host (brdfbake::validate_material); the reference assumes valid ones.
struct BrdfMaterial {
  // glTF 2.0 metallic-roughness core and Disney 2012 (baseColor, metallic, roughness).
  Rgb base_color{0.8, 0.8, 0.8};  // linear, [0, 1]
  double metallic = 0.0;          // [0, 1]
  double roughness = 0.5;         // perceptual, [0, 1]
  // Disney 2012 only, [0, 1] each (BRDF Explorer's defaults).
  double subsurface = 0.0;
  double specular = 0.5;  // F0 = 0.08 specular
  double specular_tint = 0.0;
  double anisotropic = 0.0;
  double sheen = 0.0;
  double sheen_tint = 0.5;
  double clearcoat = 0.0;  // Disney's clearcoat, and glTF's clearcoatFactor
  double clearcoat_gloss = 1.0;
  // glTF extensions.
  Rgb sheen_color{0.0, 0.0, 0.0};            // KHR_materials_sheen sheenColorFactor, [0, 1]
  double sheen_roughness = 0.0;              // sheenRoughnessFactor, [0, 1]
  double clearcoat_roughness = 0.0;          // KHR_materials_clearcoat clearcoatRoughnessFactor, [0, 1]
  double ior = 1.5;                          // KHR_materials_ior: 0 or >= 1
  double specular_factor = 1.0;              // KHR_materials_specular specularFactor, [0, 1]
  Rgb specular_color_factor{1.0, 1.0, 1.0};  // specularColorFactor, >= 0
  // Classic models. Unset colours and exponent derive from the metallic-roughness parameters
  // (classic_diffuse, classic_specular, classic_shininess).
  std::optional<Rgb> diffuse_color;   // kd, [0, 1]
  std::optional<Rgb> specular_color;  // ks (Phong, Blinn-Phong), F0 (Cook-Torrance), [0, 1]
  std::optional<double> shininess;    // Phong / Blinn-Phong exponent, [0, kMaxShininess]
  bool normalized = true;             // energy-normalised lobes (false: the textbook forms)
  MicrofacetDistribution distribution = MicrofacetDistribution::Ggx;  // Cook-Torrance's D
};

// ---- Parameter conventions of the classic models ----------------------------------------------
// kd = diffuse_color, else base_color (1 - metallic).
Rgb classic_diffuse(const BrdfMaterial& m);
// ks = specular_color, else mix(0.04, base_color, metallic) (the metallic-roughness F0).
Rgb classic_specular(const BrdfMaterial& m);
// n = shininess, else 2048^(1 - roughness) (the mapping of blinn-phong-from-pbr).
double classic_shininess(const BrdfMaterial& m);

// ---- Terms of the classic models (each cites its source in brdf.cpp; GGX's are in ggx.hpp,
// Charlie's in charlie.hpp, Burley's diffuse and Disney's subsurface in burley.hpp) ---------------
// Burley 2012, appendix B eq. 4: GTR1 (Berry), the clearcoat distribution, width a in (0, 1].
double D_GTR1(double n_dot_h, double a);
// Beckmann 1963 / Walter et al. 2007 eq. 25: normalised Beckmann distribution of a unit half vector,
// width m = alpha (floored at kMinAlpha).
double D_Beckmann(const Vec3& h, double m);
// Cook & Torrance 1982 (after Blinn 1977): V-cavity masking-shadowing min(1, 2 nh nv / vh, 2 nh nl / vh).
double G_CookTorrance(double n_dot_h, double n_dot_v, double n_dot_l, double v_dot_h);
// Phong 1975 lobe in its reciprocal BRDF form, max(0, r.v)^n, normalised by (n + 2) / (2 pi)
// (Lewis 1994) when `normalized`.
double phong_lobe(double r_dot_v, double n, bool normalized);
// Blinn 1977 lobe (n.h)^n, normalised by (n + 8) / (8 pi) (Akenine-Moller et al., Real-Time
// Rendering 3rd ed., eq. 7.49) when `normalized`.
double blinn_phong_lobe(double n_dot_h, double n, bool normalized);
// KHR_materials_sheen's E(x): the directional albedo of the Charlie sheen lobe (sheen colour 1,
// Estevez-Kulla visibility) at cosine n_dot_x, the charlie_albedo of dfg.hpp, represented per sheen
// roughness by piecewise Chebyshev series (SheenAlbedoSeries, built on first use, ~0.8 s; within
// 1e-8 of charlie_albedo, see brdf_albedo.cpp). n_dot_x < 1e-7 is evaluated at 1e-7.
double sheen_albedo(double n_dot_x, double sheen_roughness);

// The series behind sheen_albedo, which the kernels evaluate too. kSheenLowerPanels uniform panels
// of w = ln(mu) over [w_low, w_seam] = [ln 1e-7, ln 1/2] (for mu < 1/2), then kSheenUpperPanels
// uniform panels of s = (1 - mu)^exponent over [0, s_seam], s_seam = (1/2)^exponent (mu >= 1/2);
// on each, E = sum_k coefficients[panel * order + k] T_k(x), x the panel's local variable in [-1, 1].
inline constexpr int kSheenSeriesOrder = 16;
inline constexpr int kSheenLowerPanels = 16;
inline constexpr int kSheenUpperPanels = 4;
struct SheenAlbedoSeries {
  double exponent = 0.0;  // c of Estevez & Kulla's fit at alpha = sheen_roughness^2 (SheenFitExponent)
  double w_low = 0.0, w_seam = 0.0, s_seam = 0.0;
  std::vector<double> coefficients;  // (kSheenLowerPanels + kSheenUpperPanels) * kSheenSeriesOrder
};
const SheenAlbedoSeries& sheen_albedo_series(double sheen_roughness);

// ---- The models ---------------------------------------------------------------------------------
// f(wi, wo) of `model` for material `m`. Throws std::invalid_argument for a zero or non-finite
// direction.
Rgb brdf(BrdfModel model, const BrdfMaterial& m, const Vec3& wi, const Vec3& wo);

// Whether f(wi, wo) = f(wo, wi) for this material: every model but glTF with a clearcoat, whose
// layering Fresnel takes n.v (KHR_materials_clearcoat, "Discussion").
bool brdf_is_reciprocal(BrdfModel model, const BrdfMaterial& m);

// The directional albedo a(wo) = integral over the hemisphere of f(wi, wo) n.wi dwi, for
// wo = (sin theta_o, 0, cos theta_o) (azimuth 0: along the tangent, which matters only for Disney's
// anisotropy). Integrated over the half vector by nested adaptive Gauss-Kronrod quadrature split
// at the horizon (brdf_albedo.cpp), to `tolerance` absolute per channel. theta_o in [0, pi/2).
inline constexpr double kAlbedoTolerance = 1e-7;
Rgb directional_albedo(BrdfModel model, const BrdfMaterial& m, double theta_o, double tolerance = kAlbedoTolerance);

}  // namespace brdfbake::reference
