// Scalar double-precision BRDF models. See brdf.hpp for the conventions.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "brdf_internal.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/brdf.hpp"
#include "brdfbake/reference/burley.hpp"
#include "brdfbake/reference/charlie.hpp"
#include "brdfbake/reference/fresnel.hpp"
#include "brdfbake/reference/ggx.hpp"

namespace brdfbake::reference {
namespace {

using brdfbake::math::kPi;
constexpr double kInvPi = 1.0 / kPi;

double pow5(double x) {
  const double x2 = x * x;
  return x2 * x2 * x;
}
double max3(const Rgb& c) { return std::max(c.r, std::max(c.g, c.b)); }

// 1 - (1 - c)^5, the weight that Schlick's F leaves to the layer below, as -expm1(5 log1p(-c)):
// exact near grazing (c -> 0), where 1 - F would cancel to a few digits.
double schlick_complement(double c) {
  const double x = std::clamp(c, 0.0, 1.0);
  return x >= 1.0 ? 1.0 : -std::expm1(5.0 * std::log1p(-x));
}
double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double mix(double a, double b, double t) { return a + (b - a) * t; }

Rgb operator*(const Rgb& a, double s) { return {a.r * s, a.g * s, a.b * s}; }
Rgb operator+(const Rgb& a, const Rgb& b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
Rgb mix(const Rgb& a, const Rgb& b, double t) { return {mix(a.r, b.r, t), mix(a.g, b.g, t), mix(a.b, b.b, t)}; }
Rgb grey(double v) { return {v, v, v}; }

// Unit vector along v; throws for a zero or non-finite one. The largest component is divided out
// first so that tiny and huge vectors normalise without underflow or overflow.
Vec3 normalized(const Vec3& v, const char* what) {
  const double m = std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
  if (!std::isfinite(m) || !std::isfinite(v.x + v.y + v.z) || m == 0.0) {
    throw std::invalid_argument(std::string("brdf: ") + what + " is zero or not finite");
  }
  const Vec3 s{v.x / m, v.y / m, v.z / m};
  const double len = std::sqrt(dot(s, s));
  return {s.x / len, s.y / len, s.z / len};
}

// False when either direction is at or below the horizon (f = 0 there).
bool make_geometry(const Vec3& wi, const Vec3& wo, BrdfGeometry& g) {
  g.l = normalized(wi, "wi");
  g.v = normalized(wo, "wo");
  if (!(g.l.z > 0.0) || !(g.v.z > 0.0)) return false;
  g.nl = std::max(g.l.z, kBrdfMinCosine);
  g.nv = std::max(g.v.z, kBrdfMinCosine);
  // l + v has a positive z (both are above the horizon), so it never vanishes.
  g.h = normalized(Vec3{g.l.x + g.v.x, g.l.y + g.v.y, g.l.z + g.v.z}, "wi + wo");
  g.nh = g.h.z;
  g.lh = std::clamp(dot(g.l, g.h), 0.0, 1.0);
  return true;
}

// ---- Disney principled BRDF ---------------------------------------------------------------------
// Burley 2012, "Physically-Based Shading at Disney", sec. 5 and appendix B, in the formulation of
// the BRDF Explorer's disney.brdf (wdas/brdf), which is canonical here. Colours are already linear
// (disney.brdf's mon2lin gamma is not applied).
Rgb disney(const BrdfMaterial& m, const BrdfGeometry& g) {
  const Rgb base = m.base_color;
  const double lum = 0.3 * base.r + 0.6 * base.g + 0.1 * base.b;  // luminance approximation
  const Rgb tint = lum > 0.0 ? base * (1.0 / lum) : grey(1.0);    // hue and saturation only
  const Rgb spec0 = mix(mix(grey(1.0), tint, m.specular_tint) * (0.08 * m.specular), base, m.metallic);
  const Rgb sheen_color = mix(grey(1.0), tint, m.sheen_tint);

  // Diffuse: Burley's retro-reflective lobe blended with the subsurface approximation.
  const double fd = Fd_Burley(g.nv, g.nl, g.lh, m.roughness);
  const double ss = Fd_DisneySubsurface(g.nv, g.nl, g.lh, m.roughness);
  const double diffuse = mix(fd, ss, m.subsurface);

  // Specular: anisotropic GGX with separable Smith masking, Schlick Fresnel at l.h.
  const double aspect = std::sqrt(1.0 - 0.9 * m.anisotropic);
  const double r2 = m.roughness * m.roughness;
  const double ax = std::max(kDisneyMinAlpha, r2 / aspect);
  const double ay = std::max(kDisneyMinAlpha, r2 * aspect);
  const double ds = D_GGXAniso(g.h, ax, ay);
  const double gs =
      G1_SmithGGXAniso(g.nl, g.l.x, g.l.y, ax, ay) * G1_SmithGGXAniso(g.nv, g.v.x, g.v.y, ax, ay) / (4.0 * g.nl * g.nv);
  const Rgb fs = fresnel_schlick(g.lh, spec0);
  const double fh = pow5(1.0 - g.lh);

  // Sheen: a Schlick-shaped grazing lobe, tinted.
  const Rgb sheen = sheen_color * (fh * m.sheen);

  // Clearcoat: GTR1 with a fixed-width (alpha_g = 0.25) separable Smith G and F0 = 0.04 (ior 1.5).
  double coat = 0.0;
  if (m.clearcoat > 0.0) {
    const double dr = D_GTR1(g.nh, mix(0.1, 0.001, m.clearcoat_gloss));
    const double fr = F_Schlick(0.04, 1.0, g.lh);
    const double gr = G1_SmithGGX(g.nl, 0.25) * G1_SmithGGX(g.nv, 0.25) / (4.0 * g.nl * g.nv);
    coat = 0.25 * m.clearcoat * gr * fr * dr;
  }
  return (base * diffuse + sheen) * (1.0 - m.metallic) + fs * (gs * ds) + grey(coat);
}

// ---- glTF 2.0 metallic-roughness ----------------------------------------------------------------
// glTF 2.0 specification, Appendix B: specular_brdf(alpha) = D V with the GGX D and the separable
// Smith G, V = G / (4 |n.l| |n.v|). `correlated` takes Heitz 2014's height-correlated V instead.
// ggx.hpp's D_GGX(n.h) forms sin^2 as (1 - n.h)(1 + n.h), which rounds to 0 within 1e-8 rad
// of the peak, where a lobe at the alpha floor (1e-7) still lives; the same D from the components
// of h (D_GGXAniso with equal widths) is exact there.
double D_GGXIsotropic(const Vec3& h, double alpha) {
  const double a = std::max(alpha, kMinAlpha);
  return D_GGXAniso(h, a, a);
}

// Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF", eq. 2 (Charlie):
// D = (2 + 1/alpha) sin^(1/alpha) / (2 pi). charlie.hpp's D_Charlie(n.h) forms sin^2 from n.h,
// which rounds to 0 within 1e-8 rad of the normal; here sin^2 comes from the components of h near
// the normal (n.h >= 1/2), and where the lobe lives (n.h < 1/2) D_Charlie is exact already.
double D_CharlieFromHalf(const Vec3& h, double alpha) {
  if (!(h.z >= 0.0)) return 0.0;
  if (h.z < 0.5) return D_Charlie(h.z, alpha);
  const double inv_a = 1.0 / std::max(alpha, kMinAlpha);
  const double log_sin2 = std::log(h.x * h.x + h.y * h.y);
  return (2.0 + inv_a) * std::exp(0.5 * inv_a * log_sin2) / (2.0 * kPi);
}

double gltf_specular(const BrdfGeometry& g, double alpha, bool correlated) {
  const double v = correlated ? V_SmithGGXCorrelated(g.nv, g.nl, alpha)
                              : G1_SmithGGX(g.nl, alpha) * G1_SmithGGX(g.nv, alpha) / (4.0 * g.nl * g.nv);
  return D_GGXIsotropic(g.h, alpha) * v;
}

Rgb gltf(const BrdfMaterial& m, const BrdfGeometry& g, bool correlated) {
  const double spec = gltf_specular(g, m.roughness * m.roughness, correlated);
  const Rgb base = m.base_color;
  // metal_brdf = conductor_fresnel(f0 = baseColor, bsdf = specular_brdf)
  const Rgb metal = fresnel_schlick(g.lh, base) * spec;
  // dielectric_brdf = fresnel_mix(ior, base = diffuse_brdf, layer = specular_brdf), with
  // KHR_materials_specular's f0_color and weight and KHR_materials_ior's ior:
  //   f0 = min(((1 - ior)/(1 + ior))^2 f0_color, 1), fr = f0 + (1 - f0)(1 - |v.h|)^5,
  //   (1 - weight max(fr)) base + weight fr layer.
  const double f0_ior = f0_from_ior(1.0, m.ior);
  const Rgb f0{std::min(f0_ior * m.specular_color_factor.r, 1.0), std::min(f0_ior * m.specular_color_factor.g, 1.0),
               std::min(f0_ior * m.specular_color_factor.b, 1.0)};
  const Rgb fr = fresnel_schlick(g.lh, f0);
  // 1 - w max3(fr) = (1 - w) + w (1 - max3(f0)) (1 - (1 - v.h)^5): fr is increasing in f0.
  const double w = m.specular_factor;
  const double base_weight = (1.0 - w) + w * (1.0 - max3(f0)) * schlick_complement(g.lh);
  const Rgb dielectric = base * (kInvPi * base_weight) + fr * (w * spec);
  // material = mix(dielectric_brdf, metal_brdf, metallic)
  Rgb f = mix(dielectric, metal, m.metallic);

  // KHR_materials_sheen: f = f_sheen + f * sheenAlbedoScaling, f_sheen = sheenColor D_charlie V_charlie,
  // scaling = min(1 - max3(sheenColor) E(n.v), 1 - max3(sheenColor) E(n.l)). Guard: E exceeds 1 at
  // grazing angles and low sheen roughness (its visibility is not energy-conserving there), where the
  // scaling would turn negative; it is clamped at 0 (the base is then fully hidden).
  const double sheen_max = max3(m.sheen_color);
  if (sheen_max > 0.0) {
    const double alpha_s = m.sheen_roughness * m.sheen_roughness;
    const double ds = D_CharlieFromHalf(g.h, alpha_s) * V_CharlieEstevezKulla(g.nv, g.nl, alpha_s);
    const double e_v = sheen_albedo(g.nv, m.sheen_roughness);
    const double e_l = sheen_albedo(g.nl, m.sheen_roughness);
    const double scaling = std::max(0.0, std::min(1.0 - sheen_max * e_v, 1.0 - sheen_max * e_l));
    f = m.sheen_color * ds + f * scaling;
  }

  // KHR_materials_clearcoat: fresnel_coat(ior 1.5, weight = clearcoat, base = f, layer =
  // specular_brdf(clearcoatRoughness^2)) = mix(f, layer, clearcoat fr), fr = 0.04 + 0.96 (1 - |n.v|)^5
  // (the extension takes n.v, not v.h, for its layering Fresnel).
  if (m.clearcoat > 0.0) {
    const double coat = gltf_specular(g, m.clearcoat_roughness * m.clearcoat_roughness, correlated);
    const double weight = m.clearcoat * F_Schlick(0.04, 1.0, g.nv);
    const double keep = (1.0 - m.clearcoat) + m.clearcoat * 0.96 * schlick_complement(g.nv);  // 1 - weight
    f = f * keep + grey(weight * coat);
  }
  return f;
}

// ---- Classic models -----------------------------------------------------------------------------

// Phong 1975 in its reciprocal BRDF form (Lewis 1994): kd / pi + ks lobe(r.v), r = 2 (n.l) n - l the
// mirror of l, so r.v = 2 (n.l)(n.v) - l.v is symmetric in l and v.
Rgb phong(const BrdfMaterial& m, const BrdfGeometry& g) {
  const double r_dot_v = 2.0 * g.l.z * g.v.z - dot(g.l, g.v);
  return classic_diffuse(m) * kInvPi + classic_specular(m) * phong_lobe(r_dot_v, classic_shininess(m), m.normalized);
}

// Blinn 1977: kd / pi + ks lobe(n.h).
Rgb blinn_phong(const BrdfMaterial& m, const BrdfGeometry& g) {
  return classic_diffuse(m) * kInvPi + classic_specular(m) * blinn_phong_lobe(g.nh, classic_shininess(m), m.normalized);
}

// Cook & Torrance 1982: kd / pi + F D G / (4 n.l n.v), with the exact unpolarised Fresnel
// reflectance of the dielectric whose normal-incidence reflectance is F0 (their eq. for n from F0:
// eta = (1 + sqrt F0) / (1 - sqrt F0)), evaluated at v.h. The 4 (not the paper's pi) is Walter et
// al. 2007's correction, which makes D a normalised distribution of normals.
double cook_torrance_fresnel(double v_dot_h, double f0) {
  if (f0 >= 1.0) return 1.0;  // eta -> infinity: a perfect mirror
  const double s = std::sqrt(f0);
  return fresnel_dielectric(v_dot_h, (1.0 + s) / (1.0 - s));
}

Rgb cook_torrance(const BrdfMaterial& m, const BrdfGeometry& g) {
  const double alpha = m.roughness * m.roughness;
  const double d =
      m.distribution == MicrofacetDistribution::Beckmann ? D_Beckmann(g.h, alpha) : D_GGXIsotropic(g.h, alpha);
  const double vh = std::max(g.lh, kBrdfMinCosine);
  const double dg = d * G_CookTorrance(g.nh, g.nv, g.nl, vh) / (4.0 * g.nl * g.nv);
  const Rgb ks = classic_specular(m);
  const Rgb f{cook_torrance_fresnel(vh, ks.r), cook_torrance_fresnel(vh, ks.g), cook_torrance_fresnel(vh, ks.b)};
  return classic_diffuse(m) * kInvPi + f * dg;
}

// The Blinn-Phong imitation of metallic-roughness: exponent n = 2048^(1 - roughness), the
// (n + 8) / (8 pi) normalisation, c_diff = baseColor (1 - metallic), F0 = mix(0.04, baseColor,
// metallic), and Schlick's F at v.h weighting the lobe against the diffuse:
// f = (1 - F) c_diff / pi + F lobe(n.h).
Rgb blinn_phong_from_pbr(const BrdfMaterial& m, const BrdfGeometry& g) {
  const double n = std::pow(2048.0, 1.0 - m.roughness);
  const Rgb c_diff = m.base_color * (1.0 - m.metallic);
  const Rgb f0 = mix(grey(0.04), m.base_color, m.metallic);
  const Rgb f = fresnel_schlick(g.lh, f0);
  const double lobe = blinn_phong_lobe(g.nh, n, true);
  const double keep = schlick_complement(g.lh);  // 1 - F = (1 - F0)(1 - (1 - v.h)^5)
  return Rgb{(1.0 - f0.r) * keep * c_diff.r, (1.0 - f0.g) * keep * c_diff.g, (1.0 - f0.b) * keep * c_diff.b} * kInvPi +
         f * lobe;
}

}  // namespace

// ---- Parameter conventions ------------------------------------------------------------------------

Rgb classic_diffuse(const BrdfMaterial& m) {
  return m.diffuse_color ? *m.diffuse_color : m.base_color * (1.0 - m.metallic);
}

Rgb classic_specular(const BrdfMaterial& m) {
  return m.specular_color ? *m.specular_color : mix(grey(0.04), m.base_color, m.metallic);
}

double classic_shininess(const BrdfMaterial& m) {
  return m.shininess ? *m.shininess : std::pow(2048.0, 1.0 - m.roughness);
}

// ---- Terms ----------------------------------------------------------------------------------------

// Burley 2012, appendix B eq. 4 (GTR with gamma = 1, Berry 1923):
// D = (a^2 - 1) / (pi ln(a^2) (1 + (a^2 - 1) cos^2)), 1/pi at a = 1. The bracket is written as
// sin^2 + a^2 cos^2 (no cancellation at the peak).
double D_GTR1(double n_dot_h, double a) {
  if (!(n_dot_h >= 0.0)) return 0.0;
  if (a >= 1.0) return kInvPi;
  const double a2 = a * a;
  const double c = std::min(n_dot_h, 1.0);
  const double t = (1.0 - c) * (1.0 + c) + a2 * c * c;
  return (a2 - 1.0) / (kPi * std::log(a2) * t);
}

// Beckmann 1963 as normalised by Walter et al. 2007, "Microfacet Models for Refraction through
// Rough Surfaces", eq. 25: D = exp(-tan^2 / m^2) / (pi m^2 cos^4), zero below the horizon; tan^2
// from the components of the unit h (exact at the peak).
double D_Beckmann(const Vec3& h, double m) {
  if (!(h.z > 0.0)) return 0.0;
  const double mm = std::max(m, kMinAlpha);
  const double c2 = h.z * h.z;
  const double tan2 = (h.x * h.x + h.y * h.y) / c2;
  return std::exp(-tan2 / (mm * mm)) / (kPi * mm * mm * c2 * c2);
}

// Cook & Torrance 1982, "A Reflectance Model for Computer Graphics", eq. for G (from Blinn 1977's
// V-groove analysis): G = min(1, 2 (n.h)(n.v) / (v.h), 2 (n.h)(n.l) / (v.h)).
double G_CookTorrance(double n_dot_h, double n_dot_v, double n_dot_l, double v_dot_h) {
  const double k = 2.0 * n_dot_h / v_dot_h;
  return std::min(1.0, std::min(k * n_dot_v, k * n_dot_l));
}

// Phong 1975, "Illumination for Computer Generated Pictures": cos^n of the angle between the mirror
// direction and the viewer. Normalisation (n + 2) / (2 pi): Lewis 1994, "Making Shaders More
// Physically Plausible" (the lobe's albedo is then 1 at normal incidence and below 1 elsewhere).
double phong_lobe(double r_dot_v, double n, bool normalized) {
  if (!(r_dot_v > 0.0)) return 0.0;
  const double lobe = std::pow(std::min(r_dot_v, 1.0), n);
  return normalized ? lobe * (n + 2.0) / (2.0 * kPi) : lobe;
}

// Blinn 1977, "Models of Light Reflection for Computer Synthesized Pictures": (n.h)^n.
// Normalisation (n + 8) / (8 pi): Akenine-Moller, Haines & Hoffman, "Real-Time Rendering", 3rd ed.,
// eq. 7.49, an approximation of the exact (n + 2)(n + 4) / (8 pi (2^(-n/2) + n)).
double blinn_phong_lobe(double n_dot_h, double n, bool normalized) {
  if (!(n_dot_h > 0.0)) return 0.0;
  const double lobe = std::pow(std::min(n_dot_h, 1.0), n);
  return normalized ? lobe * (n + 8.0) / (8.0 * kPi) : lobe;
}

// ---- Models ---------------------------------------------------------------------------------------

Rgb brdf(BrdfModel model, const BrdfMaterial& m, const Vec3& wi, const Vec3& wo) {
  BrdfGeometry g{};
  if (!make_geometry(wi, wo, g)) return grey(0.0);
  return brdf_at(model, m, g);
}

Rgb brdf_at(BrdfModel model, const BrdfMaterial& m, const BrdfGeometry& g) {
  switch (model) {
    case BrdfModel::Disney:
      return disney(m, g);
    case BrdfModel::Gltf:
      return gltf(m, g, false);
    case BrdfModel::GltfCorrelated:
      return gltf(m, g, true);
    case BrdfModel::Lambert:
      return classic_diffuse(m) * kInvPi;
    case BrdfModel::Phong:
      return phong(m, g);
    case BrdfModel::BlinnPhong:
      return blinn_phong(m, g);
    case BrdfModel::CookTorrance:
      return cook_torrance(m, g);
    case BrdfModel::BlinnPhongFromPbr:
      return blinn_phong_from_pbr(m, g);
  }
  throw std::invalid_argument("brdf: unknown model");
}

bool brdf_is_reciprocal(BrdfModel model, const BrdfMaterial& m) {
  const bool gltf_model = model == BrdfModel::Gltf || model == BrdfModel::GltfCorrelated;
  return !(gltf_model && m.clearcoat > 0.0);
}

}  // namespace brdfbake::reference
