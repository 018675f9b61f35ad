// Bulk BRDF evaluation: f(wi, wo) of one model for many materials and directions, and the tables
// built from it (MERL, theta_i x theta_o x phi_d grid, half/difference slice, directional albedo).
//
// Compile-time choices (host/src/families/brdf_eval/evaluator.cpp defines them from the materials):
//   model: exactly one of BRDFBAKE_MODEL_DISNEY, _GLTF, _GLTF_CORRELATED, _LAMBERT, _PHONG,
//          _BLINN_PHONG, _COOK_TORRANCE, _BLINN_PHONG_FROM_PBR
//   lobes: only those some material uses are compiled in:
//          BRDFBAKE_LOBE_DIFFUSE      disney, gltf: a material with metallic < 1
//          BRDFBAKE_LOBE_SUBSURFACE   disney: subsurface > 0
//          BRDFBAKE_LOBE_SHEEN        disney: sheen > 0 (and metallic < 1); gltf: sheenColor > 0
//          BRDFBAKE_LOBE_CLEARCOAT    disney, gltf: clearcoat > 0
//          BRDFBAKE_LOBE_ANISOTROPIC  disney: anisotropic > 0
//          BRDFBAKE_LOBE_METAL        gltf: metallic > 0
//          BRDFBAKE_LOBE_SPECULAR_COLOR gltf: an RGB dielectric F0 or specularFactor < 1
//                                     (KHR_materials_specular's max3(F) weighting)
//          BRDFBAKE_CT_BECKMANN, BRDFBAKE_CT_GGX   cook-torrance: the distributions in use
//   BRDFBAKE_LANES (8 or 16, common/real.clh): directions per work-item, one per vector lane.
//
// Frame and conventions (docs/CONVENTIONS.md, "BRDF evaluation"): tangent space, n = +z, the
// anisotropy's alpha_x along +x. f is the BRDF without the cosine; f = 0 when l or v is at or
// below the horizon; above it n.l and n.v are floored at BRDFBAKE_MIN_COSINE. The per-material
// parameter block is laid out in common/brdf_params.clh.
#include "common/real.clh"
#include "common/brdf_params.clh"
#include "common/fresnel.clh"
#include "common/ggx.clh"
#include "common/charlie.clh"
#include "common/beckmann.clh"
#include "common/diffuse.clh"
#include "common/classic.clh"

typedef struct {
  realv r, g, b;
} rgbv;

#define P(slot) p[(slot)]

// ---------------------------------------------------------------------------------------------
// The models. Each evaluates f at unit l, v and h (h = (l + v) / |l + v|, given exactly by the
// caller), with nl, nv the floored cosines, s2 = h.x^2 + h.y^2, c2 = h.z^2, lh = l.h.
// ---------------------------------------------------------------------------------------------

#if defined(BRDFBAKE_MODEL_DISNEY)
// Burley 2012, "Physically-Based Shading at Disney", in disney.brdf's formulation:
// f = ((1/pi) mix(F_d, f_ss, subsurface) C + F_H sheen C_sheen)(1 - metallic)
//     + G_s F_s D_s + 0.25 clearcoat G_r F_r D_r.
inline rgbv model_lanes(realv lx, realv ly, realv vx, realv vy, realv hx, realv hy, realv nl, realv nv,
                        realv s2, realv c2, realv lh, global const real* p, global const real* sheen_table) {
  const realv fh = schlick_weight_v(lh);
  const real ax = P(BRDF_DISNEY_AX), ay = P(BRDF_DISNEY_AY);
#ifdef BRDFBAKE_LOBE_ANISOTROPIC
  const realv ds = D_GGXAniso_v(hx, hy, c2, R(1.0) / ax, R(1.0) / ay, P(BRDF_DISNEY_D_NORM));
#else
  const realv ds = D_GGX_v(s2, c2, ax * ax);
#endif
  const realv spec = ds * V1_SmithGGXAniso_v(nl, lx, ly, ax, ay) * V1_SmithGGXAniso_v(nv, vx, vy, ax, ay);
  rgbv f;
  f.r = spec * fresnel_schlick_v(lh, P(BRDF_DISNEY_SPEC0 + 0), R(1.0));
  f.g = spec * fresnel_schlick_v(lh, P(BRDF_DISNEY_SPEC0 + 1), R(1.0));
  f.b = spec * fresnel_schlick_v(lh, P(BRDF_DISNEY_SPEC0 + 2), R(1.0));
#ifdef BRDFBAKE_LOBE_DIFFUSE
  const real roughness = P(BRDF_DISNEY_ROUGHNESS);
  realv diffuse = Fd_Burley_times_pi_v(nv, nl, lh, roughness);
#ifdef BRDFBAKE_LOBE_SUBSURFACE
  diffuse = mix(diffuse, Fd_DisneySubsurface_times_pi_v(nv, nl, lh, roughness), P(BRDF_DISNEY_SUBSURFACE));
#endif
  f.r += P(BRDF_DISNEY_KD + 0) * diffuse;
  f.g += P(BRDF_DISNEY_KD + 1) * diffuse;
  f.b += P(BRDF_DISNEY_KD + 2) * diffuse;
#endif
#ifdef BRDFBAKE_LOBE_SHEEN
  f.r += P(BRDF_DISNEY_SHEEN + 0) * fh;
  f.g += P(BRDF_DISNEY_SHEEN + 1) * fh;
  f.b += P(BRDF_DISNEY_SHEEN + 2) * fh;
#endif
#ifdef BRDFBAKE_LOBE_CLEARCOAT
  // GTR1 at a = mix(0.1, 0.001, gloss), F0 = 0.04, separable Smith GGX at alpha_g = 0.25.
  const realv dr = D_GTR1_v(s2, c2, P(BRDF_DISNEY_COAT_A2), P(BRDF_DISNEY_COAT_NORM));
  const realv coat = P(BRDF_DISNEY_COAT) * dr * fresnel_schlick_v(lh, R(0.04), R(1.0)) * V_SmithGGXSeparable_v(nv, nl, R(0.0625));
  f.r += coat;
  f.g += coat;
  f.b += coat;
#endif
  return f;
}

#elif defined(BRDFBAKE_MODEL_GLTF) || defined(BRDFBAKE_MODEL_GLTF_CORRELATED)
#ifdef BRDFBAKE_MODEL_GLTF_CORRELATED
#define GLTF_V V_SmithGGXCorrelated_v
#else
#define GLTF_V V_SmithGGXSeparable_v
#endif
// glTF 2.0 Appendix B: material = mix(dielectric_brdf, metal_brdf, metallic) with
// metal_brdf = specular_brdf (f0 + (1 - f0)(1 - v.h)^5), f0 = baseColor, and
// dielectric_brdf = fresnel_mix = (1 - w max3(F)) diffuse_brdf + w F specular_brdf (KHR_materials_
// specular's form; w = 1 and a grey F without it). Then KHR_materials_sheen's albedo-scaled sheen
// layer and KHR_materials_clearcoat's coat (its Fresnel at n.v) on top.
inline rgbv model_lanes(realv lx, realv ly, realv vx, realv vy, realv hx, realv hy, realv nl, realv nv,
                        realv s2, realv c2, realv lh, global const real* p, global const real* sheen_table) {
  const real a2 = P(BRDF_GLTF_A2);
  const realv spec = D_GGX_v(s2, c2, a2) * GLTF_V(nv, nl, a2);
  rgbv f;
  f.r = (realv)R(0.0);
  f.g = (realv)R(0.0);
  f.b = (realv)R(0.0);
#ifdef BRDFBAKE_LOBE_DIFFUSE
  // 1 - w max3(F) = (1 - w) + w (1 - f0max)(1 - (1 - v.h)^5), cancellation-free at grazing
  const real wd = P(BRDF_GLTF_DIELECTRIC);
  const realv c5c = schlick_weight_complement_v(lh);
#ifdef BRDFBAKE_LOBE_SPECULAR_COLOR
  const real w = P(BRDF_GLTF_WEIGHT);
  const realv fr_r = fresnel_schlick_v(lh, P(BRDF_GLTF_F0 + 0), R(1.0));
  const realv fr_g = fresnel_schlick_v(lh, P(BRDF_GLTF_F0 + 1), R(1.0));
  const realv fr_b = fresnel_schlick_v(lh, P(BRDF_GLTF_F0 + 2), R(1.0));
  const realv base = (R(1.0) - w) + w * (R(1.0) - P(BRDF_GLTF_F0_MAX)) * c5c;
  f.r = P(BRDF_GLTF_KD + 0) * base + wd * fr_r * spec;
  f.g = P(BRDF_GLTF_KD + 1) * base + wd * fr_g * spec;
  f.b = P(BRDF_GLTF_KD + 2) * base + wd * fr_b * spec;
#else
  const realv fr = fresnel_schlick_v(lh, P(BRDF_GLTF_F0), R(1.0));
  const realv base = (R(1.0) - P(BRDF_GLTF_F0)) * c5c;
  const realv layer = wd * fr * spec;
  f.r = P(BRDF_GLTF_KD + 0) * base + layer;
  f.g = P(BRDF_GLTF_KD + 1) * base + layer;
  f.b = P(BRDF_GLTF_KD + 2) * base + layer;
#endif
#endif
#ifdef BRDFBAKE_LOBE_METAL
  const realv ms = P(BRDF_GLTF_METALLIC) * spec;
  f.r += ms * fresnel_schlick_v(lh, P(BRDF_GLTF_METAL_F0 + 0), R(1.0));
  f.g += ms * fresnel_schlick_v(lh, P(BRDF_GLTF_METAL_F0 + 1), R(1.0));
  f.b += ms * fresnel_schlick_v(lh, P(BRDF_GLTF_METAL_F0 + 2), R(1.0));
#endif
#ifdef BRDFBAKE_LOBE_SHEEN
  // f = sheenColor D_charlie V_charlie + f min(1 - max3(sheenColor) E(n.v), 1 - max3(sheenColor) E(n.l)),
  // the scaling clamped at 0 (E exceeds 1 at grazing angles; docs/CONVENTIONS.md).
  const real smax = P(BRDF_GLTF_SHEEN_MAX);
  if (smax > R(0.0)) {
    const real fa = P(BRDF_GLTF_SHEEN_FIT + 0), fb = P(BRDF_GLTF_SHEEN_FIT + 1), fc = P(BRDF_GLTF_SHEEN_FIT + 2),
               fd = P(BRDF_GLTF_SHEEN_FIT + 3), fe = P(BRDF_GLTF_SHEEN_FIT + 4), l_half = P(BRDF_GLTF_SHEEN_L_HALF);
    const realv ds = D_Charlie_v(s2, c2, P(BRDF_GLTF_SHEEN_INV_A), P(BRDF_GLTF_SHEEN_NORM));
    const CharlieFit fit = {fa, fb, fc, fd, fe, l_half};
    realv ev_l, ev_v;
    const realv lambda_l = Lambda_CharlieEstevezKulla_v(nl, fit, &ev_l);
    const realv lambda_v = Lambda_CharlieEstevezKulla_v(nv, fit, &ev_v);
    const realv vs = V_SmithCorrelated_v(nv, nl, lambda_v, lambda_l);
    global const real* table = sheen_table + (int)P(BRDF_GLTF_SHEEN_TABLE);
    const real s_seam = P(BRDF_GLTF_SHEEN_S_SEAM);
    const realv e_l = sheen_albedo_v(nl, ev_l, table, s_seam), e_v = sheen_albedo_v(nv, ev_v, table, s_seam);
    const realv scaling = fmax((realv)R(0.0), R(1.0) - smax * fmax(e_l, e_v));
    const realv sheen = ds * vs;
    f.r = P(BRDF_GLTF_SHEEN + 0) * sheen + f.r * scaling;
    f.g = P(BRDF_GLTF_SHEEN + 1) * sheen + f.g * scaling;
    f.b = P(BRDF_GLTF_SHEEN + 2) * sheen + f.b * scaling;
  }
#endif
#ifdef BRDFBAKE_LOBE_CLEARCOAT
  // coated = f (1 - clearcoat F_c) + clearcoat F_c specular_brdf(alpha_c), F_c = 0.04 + 0.96 (1 - n.v)^5.
  const real cc = P(BRDF_GLTF_COAT);
  if (cc > R(0.0)) {
    const real ac2 = P(BRDF_GLTF_COAT_A2);
    const realv w = cc * fresnel_schlick_v(nv, R(0.04), R(1.0));
    const realv keep = (R(1.0) - cc) + cc * R(0.96) * schlick_weight_complement_v(nv);  // 1 - w
    const realv coat = w * D_GGX_v(s2, c2, ac2) * GLTF_V(nv, nl, ac2);
    f.r = f.r * keep + coat;
    f.g = f.g * keep + coat;
    f.b = f.b * keep + coat;
  }
#endif
  return f;
}

#elif defined(BRDFBAKE_MODEL_LAMBERT)
// Lambert 1760: f = kd / pi.
inline rgbv model_lanes(realv lx, realv ly, realv vx, realv vy, realv hx, realv hy, realv nl, realv nv,
                        realv s2, realv c2, realv lh, global const real* p, global const real* sheen_table) {
  rgbv f;
  f.r = (realv)P(BRDF_CLASSIC_KD + 0);
  f.g = (realv)P(BRDF_CLASSIC_KD + 1);
  f.b = (realv)P(BRDF_CLASSIC_KD + 2);
  return f;
}

#elif defined(BRDFBAKE_MODEL_PHONG) || defined(BRDFBAKE_MODEL_BLINN_PHONG)
// Phong 1975 (reciprocal BRDF form, Lewis 1994): f = kd / pi + ks N max(0, r.v)^n, r the mirror of l;
// Blinn 1977: f = kd / pi + ks N (n.h)^n. N (normalised or 1) is folded into ks by the host.
// cos^n goes through sin^2 (pow_cos_v): for Phong, sin^2(r, v) = |r x v|^2 / (|r|^2 |v|^2), which
// does not care whether fp32 inputs are unit to the last bit (at n = 2048, 1 - r.v would).
inline rgbv model_lanes(realv lx, realv ly, realv vx, realv vy, realv hx, realv hy, realv nl, realv nv,
                        realv s2, realv c2, realv lh, global const real* p, global const real* sheen_table) {
  const real n = P(BRDF_CLASSIC_N);
#ifdef BRDFBAKE_MODEL_PHONG
  // r = (-l.x, -l.y, l.z); nl, nv here are the raw cosines (see the caller).
  const realv rz = nl;
  const realv cx = -ly * nv - rz * vy, cy = rz * vx + lx * nv, cz = -lx * vy + ly * vx;
  const realv rv = -lx * vx - ly * vy + rz * nv;
  const realv rr = lx * lx + ly * ly + rz * rz, vv = vx * vx + vy * vy + nv * nv;
  const realv inv_rv2 = R(1.0) / (rr * vv);
  const realv sin2 = (cx * cx + cy * cy + cz * cz) * inv_rv2, cos2 = rv * rv * inv_rv2;
  const realv lobe = rv > R(0.0) ? pow_cos_v(sin2, cos2, n) : (realv)R(0.0);
#else
  const realv lobe = pow_cos_v(s2, c2, n);
#endif
  rgbv f;
  f.r = P(BRDF_CLASSIC_KD + 0) + P(BRDF_CLASSIC_KS + 0) * lobe;
  f.g = P(BRDF_CLASSIC_KD + 1) + P(BRDF_CLASSIC_KS + 1) * lobe;
  f.b = P(BRDF_CLASSIC_KD + 2) + P(BRDF_CLASSIC_KS + 2) * lobe;
  return f;
}

#elif defined(BRDFBAKE_MODEL_COOK_TORRANCE)
// Cook & Torrance 1982: f = kd / pi + F D G / (4 n.l n.v), F the exact unpolarised dielectric
// Fresnel of the index matching F0, at v.h.
// The reference's cook_torrance_fresnel: eta = (1 + sqrt F0) / (1 - sqrt F0) from the host; a
// negative eta marks F0 = 1 (eta infinite), a perfect mirror.
inline realv cook_torrance_fresnel_v(realv v_dot_h, real eta) {
  return eta < R(0.0) ? (realv)R(1.0) : fresnel_dielectric_v(v_dot_h, eta);
}
inline rgbv model_lanes(realv lx, realv ly, realv vx, realv vy, realv hx, realv hy, realv nl, realv nv,
                        realv s2, realv c2, realv lh, global const real* p, global const real* sheen_table) {
  const real a2 = P(BRDF_CLASSIC_A2);
#if defined(BRDFBAKE_CT_BECKMANN) && defined(BRDFBAKE_CT_GGX)
  const realv d = P(BRDF_CLASSIC_BECKMANN) > R(0.5) ? D_Beckmann_v(s2, c2, a2) : D_GGX_v(s2, c2, a2);
#elif defined(BRDFBAKE_CT_BECKMANN)
  const realv d = D_Beckmann_v(s2, c2, a2);
#else
  const realv d = D_GGX_v(s2, c2, a2);
#endif
  const realv vh = fmax(lh, BRDFBAKE_MIN_COSINE);
  const realv dg = d * G_CookTorrance_v(sqrt(c2), nv, nl, vh) / (R(4.0) * nl * nv);
  rgbv f;
  f.r = P(BRDF_CLASSIC_KD + 0) + cook_torrance_fresnel_v(vh, P(BRDF_CLASSIC_KS + 0)) * dg;
  f.g = P(BRDF_CLASSIC_KD + 1) + cook_torrance_fresnel_v(vh, P(BRDF_CLASSIC_KS + 1)) * dg;
  f.b = P(BRDF_CLASSIC_KD + 2) + cook_torrance_fresnel_v(vh, P(BRDF_CLASSIC_KS + 2)) * dg;
  return f;
}

#elif defined(BRDFBAKE_MODEL_BLINN_PHONG_FROM_PBR)
// Metallic-roughness imitated by Blinn-Phong: n = 2048^(1 - roughness), lobe (n + 8)/(8 pi) (n.h)^n,
// F = F0 + (1 - F0)(1 - v.h)^5, f = (1 - F) c_diff / pi + F lobe.
inline rgbv model_lanes(realv lx, realv ly, realv vx, realv vy, realv hx, realv hy, realv nl, realv nv,
                        realv s2, realv c2, realv lh, global const real* p, global const real* sheen_table) {
  const realv lobe = P(BRDF_CLASSIC_NORM) * pow_cos_v(s2, c2, P(BRDF_CLASSIC_N));
  const realv c5c = schlick_weight_complement_v(lh);
  const realv f_r = fresnel_schlick_v(lh, P(BRDF_CLASSIC_KS + 0), R(1.0));
  const realv f_g = fresnel_schlick_v(lh, P(BRDF_CLASSIC_KS + 1), R(1.0));
  const realv f_b = fresnel_schlick_v(lh, P(BRDF_CLASSIC_KS + 2), R(1.0));
  rgbv f;  // 1 - F = (1 - F0)(1 - (1 - v.h)^5)
  f.r = P(BRDF_CLASSIC_KD + 0) * (R(1.0) - P(BRDF_CLASSIC_KS + 0)) * c5c + f_r * lobe;
  f.g = P(BRDF_CLASSIC_KD + 1) * (R(1.0) - P(BRDF_CLASSIC_KS + 1)) * c5c + f_g * lobe;
  f.b = P(BRDF_CLASSIC_KD + 2) * (R(1.0) - P(BRDF_CLASSIC_KS + 2)) * c5c + f_b * lobe;
  return f;
}

#else
#error "brdf_eval.cl needs one BRDFBAKE_MODEL_* define"
#endif

// f at unit l, v, h, zero where l or v is at or below the horizon.
inline rgbv brdf_lanes(realv lx, realv ly, realv lz, realv vx, realv vy, realv vz, realv hx, realv hy,
                       realv hz, global const real* p, global const real* sheen_table) {
  const maskv valid = lz > R(0.0) && vz > R(0.0);
#if defined(BRDFBAKE_MODEL_PHONG)
  // Phong needs the raw cosines (its lobe is built from the vectors).
  const realv nl = lz, nv = vz;
#else
  const realv nl = fmax(lz, BRDFBAKE_MIN_COSINE), nv = fmax(vz, BRDFBAKE_MIN_COSINE);
#endif
  const realv s2 = hx * hx + hy * hy, c2 = hz * hz;
  const realv lh = clamp(lx * hx + ly * hy + lz * hz, R(0.0), R(1.0));
  rgbv f = model_lanes(lx, ly, vx, vy, hx, hy, nl, nv, s2, c2, lh, p, sheen_table);
  const realv zero = (realv)R(0.0);
  f.r = select(zero, f.r, valid);
  f.g = select(zero, f.g, valid);
  f.b = select(zero, f.b, valid);
  return f;
}

// The unit half vector of l and v. l + v has h.z > 0 wherever both are above the horizon (the only
// lanes whose result is kept), but can be as short as 1e-38 when l ~ -v near the horizon: its
// largest component is divided out before normalising, so |h|^2 cannot underflow.
inline void half_vector(realv lx, realv ly, realv lz, realv vx, realv vy, realv vz, realv* hx, realv* hy,
                        realv* hz) {
  realv x = lx + vx, y = ly + vy, z = lz + vz;
  const realv inv_m = R(1.0) / fmax(fmax(fabs(x), fabs(y)), fmax(z, (realv)R(1e-30)));
  x *= inv_m;
  y *= inv_m;
  z *= inv_m;
  const realv inv_len = rsqrt(x * x + y * y + z * z);
  *hx = x * inv_len;
  *hy = y * inv_len;
  *hz = z * inv_len;
}

inline void store_rgb(rgbv f, global real* out, size_t plane, size_t at) {
  vstore_lanes(f.r, 0, out + at);
  vstore_lanes(f.g, 0, out + plane + at);
  vstore_lanes(f.b, 0, out + 2 * plane + at);
}

// ---------------------------------------------------------------------------------------------
// Pairs: dirs holds 9 planes of `stride` values (wi.x, wi.y, wi.z, wo.x, wo.y, wo.z, h.x, h.y, h.z):
// unit vectors normalised by the host in double, with the half vector h = (wi + wo) / |wi + wo|
// formed there too. (From float inputs, wi + wo of nearly opposite directions would carry the
// inputs' 6e-8 rounding of their norms into h's direction, amplified by 1 / |wi + wo|.) stride is a
// multiple of BRDFBAKE_LANES; padding lanes hold zeros and give f = 0. Work-item (i, m)
// evaluates directions i * LANES ... for material m; out holds 3 planes (r, g, b) of `stride` per
// material.
// ---------------------------------------------------------------------------------------------
kernel void brdf_pairs(global const real* dirs, const int stride, global const real* params,
                       global const real* sheen_table, global real* out) {
  const size_t at = get_global_id(0) * BRDFBAKE_LANES;
  const size_t m = get_global_id(1);
  if (at >= (size_t)stride) return;
  const size_t s = (size_t)stride;
  const realv lx = vload_lanes(0, dirs + at), ly = vload_lanes(0, dirs + s + at), lz = vload_lanes(0, dirs + 2 * s + at);
  const realv vx = vload_lanes(0, dirs + 3 * s + at), vy = vload_lanes(0, dirs + 4 * s + at),
              vz = vload_lanes(0, dirs + 5 * s + at);
  const realv hx = vload_lanes(0, dirs + 6 * s + at), hy = vload_lanes(0, dirs + 7 * s + at),
              hz = vload_lanes(0, dirs + 8 * s + at);
  const rgbv f = brdf_lanes(lx, ly, lz, vx, vy, vz, hx, hy, hz, params + m * BRDF_PARAM_STRIDE, sheen_table);
  store_rgb(f, out + m * 3 * s, s, at);
}

// ---------------------------------------------------------------------------------------------
// Half/difference angles (Rusinkiewicz 1998): h at (theta_h, phi_h = 0), the difference vector
// d = (sin td cos pd, sin td sin pd, cos td) in h's frame; wi = R_y(theta_h) d (MERL's
// half_diff_coords_to_std_coords with phi_h = 0), wo = 2 (wi.h) h - wi with wi.h = cos td.
// ---------------------------------------------------------------------------------------------
// *below marks the lanes whose wi or wo is at or below the horizon.
inline rgbv half_diff_lanes(realv th, realv td, realv pd, global const real* p, global const real* sheen_table,
                            maskv* below) {
  realv ct, cd, cp;
  const realv st = sincos(th, &ct), sd = sincos(td, &cd), sp = sincos(pd, &cp);
  const realv dx = sd * cp, dy = sd * sp;
  const realv lx = dx * ct + cd * st, ly = dy, lz = cd * ct - dx * st;
  const realv vx = R(2.0) * cd * st - lx, vy = -ly, vz = R(2.0) * cd * ct - lz;
  *below = lz <= R(0.0) || vz <= R(0.0);
  return brdf_lanes(lx, ly, lz, vx, vy, vz, st, (realv)R(0.0), ct, p, sheen_table);
}

// The MERL table (Matusik et al. 2003, as its BRDFRead / lookup_brdf_val index it): bin
// (i, j, k) = (theta_h, theta_d, phi_d), at index (i * 90 + j) * 180 + k, holds f at the bin centre
// on the reader's axes: theta_h = ((i + 0.5) / 90)^2 pi/2, theta_d = (j + 0.5) / 90 pi/2,
// phi_d = (k + 0.5) / 180 pi. Bins with wi or wo below the horizon hold -1 (MERL's marker).
// out: 3 planes of 90 * 90 * 180.
kernel void brdf_merl(global const real* params, global const real* sheen_table, const int material,
                      global real* out) {
  const int n = BRDF_MERL_THETA_H * BRDF_MERL_THETA_D * BRDF_MERL_PHI_D;
  const int at = (int)get_global_id(0) * BRDFBAKE_LANES;
  if (at >= n) return;
  const maskv b = (maskv)at + LANE_INDEX;
  const maskv i = b / (BRDF_MERL_THETA_D * BRDF_MERL_PHI_D);
  const maskv j = (b / BRDF_MERL_PHI_D) % BRDF_MERL_THETA_D;
  const maskv k = b % BRDF_MERL_PHI_D;
  const realv u = (convert_realv(i) + R(0.5)) / (real)BRDF_MERL_THETA_H;
  const realv th = u * u * (R(0.5) * BRDFBAKE_PI);
  const realv td = (convert_realv(j) + R(0.5)) / (real)BRDF_MERL_THETA_D * (R(0.5) * BRDFBAKE_PI);
  const realv pd = (convert_realv(k) + R(0.5)) / (real)BRDF_MERL_PHI_D * BRDFBAKE_PI;
  maskv below;
  rgbv f = half_diff_lanes(th, td, pd, params + material * BRDF_PARAM_STRIDE, sheen_table, &below);
  const realv marker = (realv)R(-1.0);
  f.r = select(f.r, marker, below);
  f.g = select(f.g, marker, below);
  f.b = select(f.b, marker, below);
  store_rgb(f, out, (size_t)n, (size_t)at);
}

// A half/difference slice (Burley 2012's image slice): texel (i, j) of a width x height image at
// theta_h = (i + 0.5) / width pi/2, theta_d = (j + 0.5) / height pi/2, phi_d fixed, phi_h = 0.
// out: 3 planes of width * height (row j outer); the texel count is a multiple of the lane width.
kernel void brdf_slice(global const real* params, global const real* sheen_table, const int material,
                       const int width, const int height, const real phi_d, global real* out) {
  const int n = width * height;
  const int at = (int)get_global_id(0) * BRDFBAKE_LANES;
  if (at >= n) return;
  const maskv b = (maskv)at + LANE_INDEX;
  const realv th = (convert_realv(b % width) + R(0.5)) / (real)width * (R(0.5) * BRDFBAKE_PI);
  const realv td = (convert_realv(b / width) + R(0.5)) / (real)height * (R(0.5) * BRDFBAKE_PI);
  maskv below;
  const rgbv f = half_diff_lanes(th, td, (realv)phi_d, params + material * BRDF_PARAM_STRIDE, sheen_table, &below);
  store_rgb(f, out, (size_t)((n + BRDFBAKE_LANES - 1) / BRDFBAKE_LANES * BRDFBAKE_LANES),
            (size_t)at);
}

// The theta_i x theta_o x phi_d grid: wi = (sin ti, 0, cos ti), wo = (sin to cos pd, sin to sin pd, cos to)
// at cell centres ti = (i + 0.5)/n_ti pi/2, to = (j + 0.5)/n_to pi/2, pd = (k + 0.5)/n_pd pi. Cell
// (i, j, k) at index (k * n_ti + i) * n_to + j. out: 3 planes (padded to the lane width).
kernel void brdf_grid(global const real* params, global const real* sheen_table, const int material,
                      const int n_ti, const int n_to, const int n_pd, global real* out) {
  const int n = n_ti * n_to * n_pd;
  const int at = (int)get_global_id(0) * BRDFBAKE_LANES;
  if (at >= n) return;
  const maskv b = (maskv)at + LANE_INDEX;
  const maskv j = b % n_to, i = (b / n_to) % n_ti, k = b / (n_to * n_ti);
  const realv ti = (convert_realv(i) + R(0.5)) / (real)n_ti * (R(0.5) * BRDFBAKE_PI);
  const realv to = (convert_realv(j) + R(0.5)) / (real)n_to * (R(0.5) * BRDFBAKE_PI);
  const realv pd = (convert_realv(k) + R(0.5)) / (real)n_pd * BRDFBAKE_PI;
  realv cti, cto, cpd;
  const realv sti = sincos(ti, &cti), sto = sincos(to, &cto), spd = sincos(pd, &cpd);
  const realv lx = sti, ly = (realv)R(0.0), lz = cti;
  const realv vx = sto * cpd, vy = sto * spd, vz = cto;
  realv hx, hy, hz;
  half_vector(lx, ly, lz, vx, vy, vz, &hx, &hy, &hz);
  const rgbv f = brdf_lanes(lx, ly, lz, vx, vy, vz, hx, hy, hz, params + material * BRDF_PARAM_STRIDE, sheen_table);
  store_rgb(f, out, (size_t)((n + BRDFBAKE_LANES - 1) / BRDFBAKE_LANES * BRDFBAKE_LANES),
            (size_t)at);
}

// ---------------------------------------------------------------------------------------------
// Directional albedo a(v) = integral of f(l, v) n.l dl for v = (sin to, 0, cos to), to = (i + 0.5) /
// n pi/2, by deterministic quadrature over the half vector h = (sin t cos p, sin t sin p, cos t):
//   a = integral f (n.l) 4 (v.h) sin t dt dp   (dl = 4 (v.h) dh, Walter et al. 2007; dh = sin t dt dp)
// over the h whose l = 2 (v.h) h - v is above the horizon. With n.l = A + B cos p, A = n.v cos 2t,
// B = sin_v sin 2t, every p is valid below t1 = pi/4 - to/2 and none above t2 = pi/4 + to/2
// (tan t2 = 1 / tan t1); between them p < p_e = acos(-A/B). Every model is even in p (v lies in the
// xz plane), so p runs over [0, pi] or [0, p_e] and the sum is doubled.
//   Panel A (t < t1): y = ln tan t from y_min (a thousandth of the narrowest lobe, per material) to
//   ln tan t1, composite Gauss-Legendre (n_a nodes on [0, 1]); dt = sin t cos t dy. p: the midpoint
//   rule on [0, pi] (n_p nodes), spectrally accurate for the smooth periodic integrand.
//   Panel B (t1 < t < t2): y from ln tan t1 to ln tan t2 through u = (1 - cos(pi x)) / 2, whose
//   vanishing slope at both ends absorbs the sqrt(t - t1) and sqrt(t2 - t) of p_e (n_b nodes);
//   p: Gauss-Legendre on [0, p_e] (n_p nodes).
// The polar nodes go BRDFBAKE_LANES at a time, one per lane (n_a, n_b are multiples of it,
// padded with zero-weight nodes). Node buffer q: n_a nodes, n_a weights, n_b values u(x),
// n_b weights u'(x) w, n_p midpoint cosines, n_p midpoint sines, n_p Gauss nodes, n_p Gauss weights.
// out: 3 planes of `n` per material.
// ---------------------------------------------------------------------------------------------
kernel void brdf_albedo(global const real* params, global const real* sheen_table, global const real* y_min,
                        const int n, global const real* q, const int n_a, const int n_b, const int n_p,
                        global real* out) {
  const int i = (int)get_global_id(0), m = (int)get_global_id(1);
  if (i >= n) return;
  global const real* p = params + m * BRDF_PARAM_STRIDE;
  const real to = ((real)i + R(0.5)) / (real)n * (R(0.5) * BRDFBAKE_PI);
  real n_dot_v;
  const real sin_v = sincos(to, &n_dot_v);
  const realv vx = (realv)sin_v, vy = (realv)R(0.0), vz = (realv)n_dot_v;
  const real t1 = R(0.25) * BRDFBAKE_PI - R(0.5) * to;
  const real ya = log(tan(t1)), y0 = y_min[m];
  global const real* qa = q;
  global const real* qb = q + 2 * n_a;
  global const real* qp = q + 2 * n_a + 2 * n_b;
  realv acc_r = (realv)R(0.0), acc_g = (realv)R(0.0), acc_b = (realv)R(0.0);

  // Panel A.
  if (ya > y0) {
    const real span = ya - y0;
    for (int k = 0; k < n_a; k += BRDFBAKE_LANES) {
      const realv e = exp(y0 + span * vload_lanes(0, qa + k));  // tan t
      const realv cos_t = rsqrt(R(1.0) + e * e), sin_t = e * cos_t;
      // weight of a node: span w_k (dt/dy = sin t cos t) sin t (pi / n_p) 2
      const realv wt = span * vload_lanes(0, qa + n_a + k) * sin_t * sin_t * cos_t * (R(2.0) * BRDFBAKE_PI / (real)n_p);
      for (int j = 0; j < n_p; ++j) {
        const real cp = qp[j], sp = qp[n_p + j];
        const realv hx = sin_t * cp, hy = sin_t * sp, hz = cos_t;
        const realv vh = sin_v * hx + n_dot_v * hz;
        // l lies above the horizon by construction, but rounding next to t1 (or p_e) gives n.l of
        // 0 or -1e-8, where the sheen's fitted Lambda has no limit (docs/CONVENTIONS.md): the BRDF is
        // evaluated at n.l >= 1e-7 (the DFG kernel's floor), the weight keeps the true (n.l)+.
        const realv lz_true = R(2.0) * vh * hz - n_dot_v;
        const realv lx = R(2.0) * vh * hx - sin_v, ly = R(2.0) * vh * hy, lz = fmax(lz_true, R(1e-7));
        const rgbv f = brdf_lanes(lx, ly, lz, vx, vy, vz, hx, hy, hz, p, sheen_table);
        const realv w = wt * R(4.0) * vh * fmax(lz_true, R(0.0));
        acc_r += w * f.r;
        acc_g += w * f.g;
        acc_b += w * f.b;
      }
    }
  }
  // Panel B.
  if (sin_v > R(0.0)) {
    const real y_lo = ya, span = -R(2.0) * ya;
    for (int k = 0; k < n_b; k += BRDFBAKE_LANES) {
      const realv e = exp(y_lo + span * vload_lanes(0, qb + k));
      const realv cos_t = rsqrt(R(1.0) + e * e), sin_t = e * cos_t;
      const realv a = n_dot_v * (cos_t - sin_t) * (cos_t + sin_t), bb = sin_v * R(2.0) * sin_t * cos_t;
      const realv p_e = acos(clamp(-a / bb, R(-1.0), R(1.0)));
      const realv wt = span * vload_lanes(0, qb + n_b + k) * sin_t * sin_t * cos_t * R(2.0) * p_e;
      for (int j = 0; j < n_p; ++j) {
        realv cp;
        const realv sp = sincos(p_e * qp[2 * n_p + j], &cp);
        const realv hx = sin_t * cp, hy = sin_t * sp, hz = cos_t;
        const realv vh = sin_v * hx + n_dot_v * hz;
        // l lies above the horizon by construction, but rounding next to t1 (or p_e) gives n.l of
        // 0 or -1e-8, where the sheen's fitted Lambda has no limit (docs/CONVENTIONS.md): the BRDF is
        // evaluated at n.l >= 1e-7 (the DFG kernel's floor), the weight keeps the true (n.l)+.
        const realv lz_true = R(2.0) * vh * hz - n_dot_v;
        const realv lx = R(2.0) * vh * hx - sin_v, ly = R(2.0) * vh * hy, lz = fmax(lz_true, R(1e-7));
        const rgbv f = brdf_lanes(lx, ly, lz, vx, vy, vz, hx, hy, hz, p, sheen_table);
        const realv w = wt * qp[3 * n_p + j] * R(4.0) * vh * fmax(lz_true, R(0.0));
        acc_r += w * f.r;
        acc_g += w * f.g;
        acc_b += w * f.b;
      }
    }
  }
  const real sums[3] = {lanes_sum(acc_r), lanes_sum(acc_g), lanes_sum(acc_b)};
  for (int c = 0; c < 3; ++c) out[((size_t)m * 3 + (size_t)c) * (size_t)n + (size_t)i] = sums[c];
}
