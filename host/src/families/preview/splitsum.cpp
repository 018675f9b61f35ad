// The split-sum render of each target (splitsum.hpp). Every step names the engine's own function
// (docs/ENGINES.md); the arithmetic is fp32, as in the shaders.
#include "families/preview/splitsum.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "brdfbake/error.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/sh.hpp"
#include "families/preview/iridescence.hpp"
#include "families/preview/splitsum_babylon.hpp"

namespace brdfbake::detail::preview {

namespace {

// The polynomials poly_k of the 9 functions: 1, y, z, x, xy, yz, 3z^2 - 1, xz, x^2 - y^2.
void poly9(float x, float y, float z, float p[9]) {
  p[0] = 1.0f;
  p[1] = y;
  p[2] = z;
  p[3] = x;
  p[4] = x * y;
  p[5] = y * z;
  p[6] = 3.0f * z * z - 1.0f;
  p[7] = x * z;
  p[8] = x * x - y * y;
}

// Padded levels of a cube (cube.clh's layout): each face (s + 2)^2 RGB texels, its border holding
// the neighbouring face's texel nearest to the extended texel centre, a corner the mean of the three
// texels around it: the seamless cube filtering of OpenGL 4.6, 8.13.1 (GL_TEXTURE_CUBE_MAP_SEAMLESS,
// always on in WebGL 2 and on in Filament).
template <class Level>
Level pad(const CubeLevels& cube, int l) {
  Level out;
  const int s = cube.level_size(l);
  out.size = s;
  const size_t p = size_t(s) + 2;
  out.rgb.assign(6 * p * p * 3, 0.0f);
  auto fetch = [&](int face, int i, int j, float* rgb) {
    const bool in_i = i >= 0 && i < s, in_j = j >= 0 && j < s;
    auto neighbour = [&](int ii, int jj, float* o) {
      const double a = 2.0 * (ii + 0.5) / s - 1.0, b = 2.0 * (jj + 0.5) / s - 1.0;
      int nf = 0;
      double na = 0, nb = 0;
      math::cube_face_coords(math::cube_plane_point(face, a, b), nf, na, nb);
      const int ni = std::clamp(int(std::floor(0.5 * (na + 1.0) * s)), 0, s - 1);
      const int nj = std::clamp(int(std::floor(0.5 * (nb + 1.0) * s)), 0, s - 1);
      const float* t = cube.texel(l, nf, ni, nj);
      for (int c = 0; c < 3; ++c) o[c] = t[c];
    };
    if (in_i && in_j) {
      const float* t = cube.texel(l, face, i, j);
      for (int c = 0; c < 3; ++c) rgb[c] = t[c];
    } else if (in_i || in_j) {
      neighbour(i, j, rgb);
    } else {
      const int ci = std::clamp(i, 0, s - 1), cj = std::clamp(j, 0, s - 1);
      float a[3], b[3];
      neighbour(ci, j, a);
      neighbour(i, cj, b);
      const float* t = cube.texel(l, face, ci, cj);
      for (int c = 0; c < 3; ++c) rgb[c] = (a[c] + b[c] + t[c]) / 3.0f;
    }
  };
  for (int f = 0; f < 6; ++f)
    for (int j = -1; j <= s; ++j)
      for (int i = -1; i <= s; ++i) fetch(f, i, j, &out.rgb[3 * ((size_t(f) * p + size_t(j + 1)) * p + size_t(i + 1))]);
  return out;
}

// The face and face coordinates of a direction (OpenGL 4.6, table 8.19), in fp32.
int face_of(const Vec3& d, float* a, float* b) {
  const float x = float(d.x), y = float(d.y), z = float(d.z);
  const float ax = std::fabs(x), ay = std::fabs(y), az = std::fabs(z);
  if (ax >= ay && ax >= az) {
    *a = (x >= 0.0f ? -z : z) / ax;
    *b = -y / ax;
    return x >= 0.0f ? 0 : 1;
  }
  if (ay >= az) {
    *a = x / ay;
    *b = (y >= 0.0f ? z : -z) / ay;
    return y >= 0.0f ? 2 : 3;
  }
  *a = (z >= 0.0f ? x : -x) / az;
  *b = -y / az;
  return z >= 0.0f ? 4 : 5;
}

// Babylon.js's renderer (sphericalPolynomial.ts): the harmonics its shader evaluates from a spherical
// polynomial, SphericalHarmonics.FromPolynomial then preScaleForRendering (times
// SH3ylmBasisConstants, which carry the Condon-Shortley signs): 9 x RGB in the order l00, l1-1, l10,
// l11, l2-2, l2-1, l20, l21, l22. p: x, y, z, xx, yy, zz, yz, zx, xy.
std::vector<double> babylon_prescaled_harmonics(const std::vector<double>& p) {
  auto at = [&](int k, int c) { return p[size_t(3 * k + c)]; };
  const double basis[9] = {
      std::sqrt(1.0 / (4.0 * M_PI)),  -std::sqrt(3.0 / (4.0 * M_PI)),  std::sqrt(3.0 / (4.0 * M_PI)),
      -std::sqrt(3.0 / (4.0 * M_PI)), std::sqrt(15.0 / (4.0 * M_PI)),  -std::sqrt(15.0 / (4.0 * M_PI)),
      std::sqrt(5.0 / (16.0 * M_PI)), -std::sqrt(15.0 / (4.0 * M_PI)), std::sqrt(15.0 / (16.0 * M_PI))};
  std::vector<double> h(27);
  for (int c = 0; c < 3; ++c) {
    const double x = at(0, c), y = at(1, c), z = at(2, c), xx = at(3, c), yy = at(4, c), zz = at(5, c), yz = at(6, c),
                 zx = at(7, c), xy = at(8, c);
    const double l[9] = {xx * 0.376127 + yy * 0.376127 + zz * 0.376126,
                         -y * 0.977204,
                         z * 0.977204,
                         -x * 0.977204,
                         xy * 1.16538,
                         -yz * 1.16538,
                         zz * 1.34567 - xx * 0.672834 - yy * 0.672834,
                         -zx * 1.16538,
                         xx * 1.16538 - yy * 1.16538};
    for (int k = 0; k < 9; ++k) h[size_t(3 * k + c)] = l[k] * M_PI * basis[k];
  }
  return h;
}

// Babylon.js's SphericalPolynomial.FromHarmonics (updateFromHarmonics) of harmonics h (9 x RGB).
std::vector<double> babylon_polynomial_from(const std::vector<double>& h) {
  std::vector<double> p(27);
  for (int c = 0; c < 3; ++c) {
    auto at = [&](int k) { return h[size_t(3 * k + c)]; };
    const double v[9] = {-1.02333 * at(3),
                         -1.02333 * at(1),
                         1.02333 * at(2),
                         0.886277 * at(0) - 0.247708 * at(6) + 0.429043 * at(8),
                         0.886277 * at(0) - 0.247708 * at(6) - 0.429043 * at(8),
                         0.886277 * at(0) + 0.495417 * at(6),
                         -0.858086 * at(5),
                         -0.858086 * at(7),
                         0.858086 * at(4)};
    for (int k = 0; k < 9; ++k) p[size_t(3 * k + c)] = v[k] / M_PI;
  }
  return p;
}

float mixf(float a, float b, float t) { return a + (b - a) * t; }

// The glTF-Sample-Viewer's f0 (material_info.glsl, getIorInfo then getMetallicRoughnessInfo and
// getSpecularInfo): mix(min(f0_ior specularColorFactor, 1), baseColor, metallic), without the
// specular factor (its specularWeight); preview_f0 of the material with specular 1.
Rgb sample_viewer_f0(const PreviewMaterial& m) {
  PreviewMaterial unweighted = m;
  unweighted.specular = 1.0;
  return preview_f0(unweighted);
}
float pow5(float x) {
  const float x2 = x * x;
  return x2 * x2 * x;
}

}  // namespace

SplitSum::SplitSum(BakeFiles files, SplitSumOptions options) : files_(std::move(files)), options_(options) {
  // Babylon.js 8.46.2's glTF loader (EXT_lights_image_based.ts): a RawCubeTexture, whose gammaSpace
  // stays true, so the PBR shader raises every reflection sample to 2.2 (GAMMAREFLECTION); and
  // `enableSpecularAntiAliasing = true` on every material it makes (glTFLoader.ts, _createDefaultMaterial)
  reflection_gamma_ = files_.target == EngineTarget::Gltf;
  specular_aa_ = files_.target == EngineTarget::Gltf;
  // Babylon.js evaluates harmonics pre-scaled from the spherical polynomial (the .env's), or from the
  // polynomial its glTF loader makes of irradianceCoefficients (EXT_lights_image_based.ts:
  // FromArray, convertIrradianceToLambertianRadiance, SphericalPolynomial.FromHarmonics).
  if (files_.diffuse == DiffuseSource::BabylonPolynomial) {
    harmonics_ = babylon_prescaled_harmonics(files_.sh);
  } else if (files_.diffuse == DiffuseSource::GltfSh) {
    std::vector<double> lambertian = files_.sh;
    for (double& v : lambertian) v /= M_PI;
    harmonics_ = babylon_prescaled_harmonics(babylon_polynomial_from(lambertian));
  }
  for (int l = 0; l < files_.specular.level_count(); ++l) levels_.push_back(pad<Level>(files_.specular, l));
  if (files_.target == EngineTarget::Gltf) {
    // EXT_lights_image_based.ts's RawCubeTexture has log2(specularImageSize) + 1 levels and
    // _UploadLevelsAsync fills those beyond the file's specularImages with zeros: a LOD past the last
    // level (alphaG above 1 with specular anti-aliasing) blends towards black
    const int full = int(std::lround(std::log2(double(files_.specular.size)))) + 1;
    for (int l = files_.specular.level_count(); l < full; ++l) {
      Level z;
      z.size = files_.specular.level_size(l);
      z.rgb.assign(6 * size_t(z.size + 2) * size_t(z.size + 2) * 3, 0.0f);
      levels_.push_back(std::move(z));
    }
  }
  if (!files_.irradiance.levels.empty()) irradiance_.push_back(pad<Level>(files_.irradiance, 0));
  for (int l = 0; l < files_.sheen.level_count(); ++l) sheen_levels_.push_back(pad<Level>(files_.sheen, l));
  if (files_.diffuse == DiffuseSource::OurSh && files_.sh_order < 3)
    throw Error("'" + files_.diffuse_file + "': SH of " + std::to_string(files_.sh_order) + " bands (at least 3)");
}

namespace {

// GL_LINEAR on one padded face of a level.
template <class Level>
void sample_face(const Level& lv, int face, float a, float b, float out[3]) {
  const int s = lv.size;
  const size_t p = size_t(s) + 2;
  // texel coordinates (texel centres at i + 0.5), in the padded face (+1)
  const float x = 0.5f * (a + 1.0f) * float(s) + 0.5f, y = 0.5f * (b + 1.0f) * float(s) + 0.5f;
  const int x0 = std::min(int(x), s), y0 = std::min(int(y), s);
  const float tx = x - float(x0), ty = y - float(y0);
  const float* t = &lv.rgb[3 * ((size_t(face) * p + size_t(y0)) * p + size_t(x0))];
  for (int c = 0; c < 3; ++c) {
    const float top = mixf(t[c], t[3 + c], tx), bottom = mixf(t[3 * p + size_t(c)], t[3 * p + 3 + size_t(c)], tx);
    out[c] = mixf(top, bottom, ty);
  }
}

}  // namespace

void SplitSum::bilinear(int level, int face, float a, float b, float out[3]) const {
  const std::vector<Level>& ls = level < 0 ? irradiance_ : levels_;
  sample_face(ls[size_t(level < 0 ? 0 : level)], face, a, b, out);
}

void SplitSum::trilinear_in(const std::vector<Level>& chain, const Vec3& d, float lod, float out[3]) {
  // textureLod: lod clamped to [0, levels - 1], linear between the two nearest levels
  float a = 0, b = 0;
  const int face = face_of(d, &a, &b);
  const float clamped = std::clamp(lod, 0.0f, float(chain.size() - 1));
  const int l0 = std::min(int(clamped), int(chain.size()) - 1);
  const float t = clamped - float(l0);
  sample_face(chain[size_t(l0)], face, a, b, out);
  if (t > 0.0f && l0 + 1 < int(chain.size())) {
    float hi[3];
    sample_face(chain[size_t(l0) + 1], face, a, b, hi);
    for (int c = 0; c < 3; ++c) out[c] = mixf(out[c], hi[c], t);
  }
}

void SplitSum::trilinear(const Vec3& d, float lod, float out[3]) const { trilinear_in(levels_, d, lod, out); }

void SplitSum::reflection(const Vec3& d, float lod, float out[3]) const {
  trilinear(d, lod, out);
  if (reflection_gamma_)  // helperFunctions.fx toLinearSpace: pow(color, LinearEncodePowerApprox 2.2)
    for (int c = 0; c < 3; ++c) out[c] = std::pow(out[c], 2.2f);
}

namespace {

// texture(lut, vec2(n_dot_v, roughness)) of a table's channels first .. first + channels - 1: bilinear,
// clamp to edge, texel centres at (i + 0.5) / N; the n_dot_v axis sqrt-spaced where the table says so.
void lut_lookup(const Table& t, bool sqrt_n_dot_v, float n_dot_v, float roughness, int channels, float* c,
                int first = 0) {
  const float u = sqrt_n_dot_v ? std::sqrt(std::max(n_dot_v, 0.0f)) : n_dot_v;
  auto split = [](float uv, int n, int* i0, float* f) {
    const float x = std::clamp(uv * float(n) - 0.5f, 0.0f, float(n - 1));
    *i0 = std::min(int(x), std::max(n - 2, 0));
    *f = n > 1 ? x - float(*i0) : 0.0f;
  };
  int i0 = 0, j0 = 0;
  float fx = 0, fy = 0;
  split(u, t.width, &i0, &fx);
  split(roughness, t.height, &j0, &fy);
  const int i1 = std::min(i0 + 1, t.width - 1), j1 = std::min(j0 + 1, t.height - 1);
  for (int k = 0; k < channels; ++k) {
    const int ch = first + k;
    c[k] = mixf(mixf(t.at(i0, j0, ch), t.at(i1, j0, ch), fx), mixf(t.at(i0, j1, ch), t.at(i1, j1, ch), fx), fy);
  }
}

}  // namespace

float SplitSum::charlie(float n_dot_v, float sheen_roughness) const {
  float e = 0.0f;
  if (files_.target == EngineTarget::Filament)  // sheenDFG: prefilteredDFG(...).z of Filament's own table
    lut_lookup(files_.dfg, false, n_dot_v, sheen_roughness, 1, &e, 2);
  else
    lut_lookup(files_.charlie, files_.charlie_sqrt_n_dot_v, n_dot_v, sheen_roughness, 1, &e);
  return e;
}

void SplitSum::dfg(float n_dot_v, float roughness, float* bias, float* albedo) const {
  float c[2];
  lut_lookup(files_.dfg, files_.dfg_sqrt_n_dot_v, n_dot_v, roughness, 2, c);
  if (files_.dfg_multiscatter) {
    *bias = c[0];
    *albedo = c[1];
  } else {
    *bias = c[1];
    *albedo = c[0] + c[1];  // scale + bias
  }
}

void SplitSum::diffuse(const Vec3& n, float out[3]) const {
  const std::vector<double>& c = files_.sh;
  float p[9];
  poly9(float(n.x), float(n.y), float(n.z), p);
  switch (files_.diffuse) {
    case DiffuseSource::OurSh: {
      // docs/CONVENTIONS.md: E(n) / pi = sum c_lm Y_lm(n)
      const std::vector<double> y = math::sh_basis(files_.sh_order, n);
      for (int ch = 0; ch < 3; ++ch) {
        double e = 0.0;
        for (size_t k = 0; k < y.size(); ++k) e += c[3 * k + size_t(ch)] * y[k];
        out[ch] = float(e);
      }
      return;
    }
    case DiffuseSource::FilamentSh:
      // Filament light_indirect.fs, Irradiance_SphericalHarmonics: max(sum sh_k poly_k(n), 0)
      for (int ch = 0; ch < 3; ++ch) {
        float e = 0.0f;
        for (size_t k = 0; k < 9; ++k) e += float(c[3 * k + size_t(ch)]) * p[k];
        out[ch] = std::max(e, 0.0f);
      }
      return;
    case DiffuseSource::GltfSh:
    case DiffuseSource::BabylonPolynomial:
      // Babylon.js's harmonicsFunctions.fx, computeEnvironmentIrradiance: sum of the pre-scaled
      // harmonics times 1, y, z, x, yx, yz, 3z^2 - 1, zx, x^2 - y^2
      for (int ch = 0; ch < 3; ++ch) {
        float e = 0.0f;
        for (size_t k = 0; k < 9; ++k) e += float(harmonics_[3 * k + size_t(ch)]) * p[k];
        out[ch] = e;
      }
      return;
    case DiffuseSource::IrradianceCube: {
      // glTF-Sample-Viewer ibl.glsl, getDiffuseLight: texture(u_LambertianEnvSampler, n)
      float a = 0, b = 0;
      const int face = face_of(n, &a, &b);
      bilinear(-1, face, a, b, out);
      return;
    }
  }
}

Rgb SplitSum::sky(const Vec3& d) const {
  float a = 0, b = 0, o[3];
  const int face = face_of(d, &a, &b);
  bilinear(0, face, a, b, o);
  return {o[0], o[1], o[2]};
}

namespace {

// KHR_materials_iridescence where the engine mixes the film into its F0 (generic's runtime, Babylon.js's
// iridescenceBlock): f0 = mix(f0, evalIridescence(1, iridescenceIor, n.v, thickness, f0), factor);
// unchanged without a film.
void iridescent_f0(const PreviewMaterial& m, float n_dot_v, float f0[3]) {
  float factor = 0.0f, fresnel[3];
  if (!split_sum_film(m, n_dot_v, f0, &factor, fresnel)) return;
  for (int c = 0; c < 3; ++c) f0[c] = f0[c] + (fresnel[c] - f0[c]) * factor;
}

}  // namespace

void SplitSum::base_generic(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const {
  const float nx = in.nx, ny = in.ny, nz = in.nz, vx = in.vx, vy = in.vy, vz = in.vz, dot_nv = in.dot_nv;
  const float* cd = in.cd;
  const float* irr = in.irr;
  float f0[3] = {in.f0[0], in.f0[1], in.f0[2]};
  const float levels_minus_one = in.levels_minus_one;
  const float f90 = in.f90;
  // docs/CONVENTIONS.md's runtime: lod = (levels - 1) roughness, specular = prefiltered x
  // (F90 bias + (albedo - bias) F0) x (1 + F0 (1 / albedo - 1)) (ggx-multiscatter) or F0 scale
  // + F90 bias
  const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.roughness);
  const Vec3 refl{double(2.0f * nv * nx - vx), double(2.0f * nv * ny - vy), double(2.0f * nv * nz - vz)};
  float light[3], bias = 0, albedo = 0;
  trilinear(refl, levels_minus_one * r, light);
  dfg(nv, r, &bias, &albedo);
  iridescent_f0(m, nv, f0);  // KHR_materials_iridescence: F0 = mix(F0, F_irid(n.v), iridescenceFactor)
  for (int c = 0; c < 3; ++c) {
    const float e = f90 * bias + (albedo - bias) * f0[c];
    const float k = files_.dfg_multiscatter ? 1.0f + f0[c] * (1.0f / albedo - 1.0f) : 1.0f;
    out[c] = light[c] * e * k + cd[c] * irr[c];
  }
}

void SplitSum::base_filament(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const {
  const float nx = in.nx, ny = in.ny, nz = in.nz, vx = in.vx, vy = in.vy, vz = in.vz, dot_nv = in.dot_nv;
  const float* cd = in.cd;
  const float* irr = in.irr;
  float f0[3] = {in.f0[0], in.f0[1], in.f0[2]};
  const float levels_minus_one = in.levels_minus_one;
  // surface_shading_lit.fs getRoughnessPixelParams: under a clear coat (MATERIAL_HAS_CLEAR_COAT_ROUGHNESS,
  // which gltfio's materials set) the base is at least as rough as the coat, mixed by clearCoat:
  // mix(r, max(r, clearCoatPerceptualRoughness), clearCoat), the coat's clamped as evaluateClearCoatIBL's;
  // then perceptualRoughness clamped to [MIN_PERCEPTUAL_ROUGHNESS 0.045, 1] (common_material.fs),
  // roughness = perceptualRoughness^2; shading_NoV = clampNoV(dot(n, v)) = max(NoV, 1e-4)
  float base_pr = float(m.roughness);
  if (m.clearcoat > 0.0)
    base_pr =
        mixf(base_pr, std::max(base_pr, std::clamp(float(m.clearcoat_roughness), 0.045f, 1.0f)), float(m.clearcoat));
  const float pr = std::clamp(base_pr, 0.045f, 1.0f), a = pr * pr;
  const float nv = std::max(dot_nv, 1e-4f);
  float bias = 0, albedo = 0;
  dfg(nv, pr, &bias, &albedo);  // PrefilteredDFG_LUT(perceptualRoughness, NoV)
  // getReflectedVector -> getSpecularDominantDirection: mix(r, n, roughness^2), r = reflect(-v, n)
  const float rx = 2.0f * dot_nv * nx - vx, ry = 2.0f * dot_nv * ny - vy, rz = 2.0f * dot_nv * nz - vz;
  const float s = a * a;
  const Vec3 dir{mixf(rx, nx, s), mixf(ry, ny, s), mixf(rz, nz, s)};
  float light[3];
  trilinear(dir, levels_minus_one * pr * (2.0f - pr), light);  // perceptualRoughnessToLod
  for (int c = 0; c < 3; ++c) {
    const float e = mixf(bias, albedo, f0[c]);                // specularDFG (F90 1)
    const float k = 1.0f + f0[c] * (1.0f / albedo - 1.0f);    // energyCompensation
    out[c] = e * light[c] * k + cd[c] * irr[c] * (1.0f - e);  // evaluateIBL: Fr + Fd
  }
}

void SplitSum::base_babylon(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const {
  const float nx = in.nx, ny = in.ny, nz = in.nz, vx = in.vx, vy = in.vy, vz = in.vz, dot_nv = in.dot_nv;
  const float* irr = in.irr;
  float f0[3] = {in.f0[0], in.f0[1], in.f0[2]};
  const float specular = in.specular;
  // pbrBlockGeometryInfo: NdotV = absEps(dot(n, v)) = |NdotV| + 1e-7;
  // alphaG = convertRoughnessToAverageSlope(roughness) = roughness^2 + MINIMUMVARIANCE (0.0005),
  // + AARoughnessFactors.y under SPECULARAA (getAARoughnessFactors: 0.75 sqrt(slopeSquare))
  const float nv = std::fabs(dot_nv) + 1e-7f, r = float(m.roughness);
  const float alpha_g = r * r + 0.0005f + in.aa_alpha_g;
  // sampleReflectionTexture: lod = getLodFromAlphaG(size, alphaG) * lodGenerationScale + offset
  const float lod = std::log2(float(files_.specular.size) * alpha_g) * float(files_.lod_scale);
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  float light[3], bias = 0, albedo = 0;
  reflection(refl, lod, light);
  // reflectionBlock, MIX_IBL_RADIANCE_WITH_IRRADIANCE (PBRBRDFConfiguration's default since 7.45):
  // environmentRadiance = mix(environmentRadiance, environmentIrradiance, alphaG)
  if (options_.babylon_mix_ibl_radiance_with_irradiance)
    for (int c = 0; c < 3; ++c) light[c] = mixf(light[c], irr[c], alpha_g);
  dfg(nv, r, &bias, &albedo);  // getBRDFLookup(NdotV, roughness)
  // pbrBlockReflectivity.fx, LEGACY_SPECULAR_ENERGY_CONSERVATION (PBRBRDFConfiguration's default in
  // 8.46.2), metallic workflow: dielectricF0 = reflectivityColor.a (((ior - 1) / (ior + 1))^2) x
  // specularWeight (specularFactor); surfaceAlbedo = baseColor (1 - dielectricF0 surfaceReflectivityColor)
  // (1 - metallic); reflectanceF90 = colorReflectanceF90 = specularWeight
  const float f0_ior = float(std::pow((m.ior - 1.0) / (m.ior + 1.0), 2.0));
  const float spec_color[3] = {float(m.specular_color.r), float(m.specular_color.g), float(m.specular_color.b)};
  const float base[3] = {float(m.base_color.r), float(m.base_color.g), float(m.base_color.b)};
  const float r90 = specular;
  // pbrBlockIridescence.fx iridescenceBlock (KHR_materials_iridescence.ts: intensity, IOR, maximum
  // thickness): specularEnvironmentR0 = mix(R0, evalIridescence(1, IOR, NdotV, thickness, R0), intensity)
  iridescent_f0(m, nv, f0);
  for (int c = 0; c < 3; ++c) {
    // getReflectanceFromBRDFLookup (height-correlated, metallic workflow): (R90 - R0) x + R0 y;
    // getEnergyConservationFactor: 1 + R0 (1 / y - 1)
    const float reflectance = (r90 - f0[c]) * bias + f0[c] * albedo;
    const float k = 1.0f + f0[c] * (1.0f / albedo - 1.0f);
    const float surface_albedo = base[c] * (1.0f - f0_ior * specular * spec_color[c]) * (1.0f - float(m.metallic));
    out[c] = light[c] * reflectance * k + irr[c] * surface_albedo;  // finalRadianceScaled + finalIrradiance
  }
}

void SplitSum::base_khronos_viewer(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const {
  const float nx = in.nx, ny = in.ny, nz = in.nz, vx = in.vx, vy = in.vy, vz = in.vz, dot_nv = in.dot_nv;
  const float* cd = in.cd;
  const float* irr = in.irr;
  const float levels_minus_one = in.levels_minus_one;
  const float specular = in.specular;
  // ibl.glsl getIBLRadianceGGX and getIBLRadianceLambertian; material_info.glsl getIorInfo and
  // getSpecularInfo: f0 = mix(min(f0_ior specularColorFactor, 1), baseColor, metallic) without the
  // specular factor, which both functions apply as specularWeight (to metals too)
  const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.roughness);
  const float lod = r * levels_minus_one;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  float light[3], bias = 0, albedo = 0;
  trilinear(refl, lod, light);
  dfg(std::clamp(nv, 0.0f, 1.0f), std::clamp(r, 0.0f, 1.0f), &bias, &albedo);
  const float fa = albedo - bias, fb = bias;  // f_ab: scale, bias
  const Rgb f0_sv = sample_viewer_f0(m);
  const float f0v[3] = {float(f0_sv.r), float(f0_sv.g), float(f0_sv.b)}, sw = specular;
  // KHR_materials_iridescence (pbr.frag): iridescenceFresnel = evalIridescence(1, iridescenceIor, NdotV,
  // thickness, f0); getIBLRadianceGGXIridescence mixes it into k_S, getIBLRadianceLambertianIridescence
  // mixes F0 with max3(Schlick_to_F0(iridescenceFresnel, NdotV))
  float film = 0.0f, film_fresnel[3] = {0, 0, 0}, f0l[3] = {f0v[0], f0v[1], f0v[2]};
  const bool iridescent = split_sum_film(m, nv, f0v, &film, film_fresnel);
  if (iridescent) {
    const float f0_max = std::max(
        {schlick_to_f0(film_fresnel[0], nv), schlick_to_f0(film_fresnel[1], nv), schlick_to_f0(film_fresnel[2], nv)});
    for (int c = 0; c < 3; ++c) f0l[c] = mixf(f0v[c], f0_max, film);
  }
  for (int c = 0; c < 3; ++c) {
    const float fr = std::max(1.0f - r, f0v[c]) - f0v[c];
    const float ks0 = f0v[c] + fr * pow5(1.0f - nv);
    const float ks = iridescent ? mixf(ks0, film_fresnel[c], film) : ks0;
    const float frd = std::max(1.0f - r, f0l[c]) - f0l[c];
    const float ksd = f0l[c] + frd * pow5(1.0f - nv);
    const float fss_ess = sw * ksd * fa + fb;  // getIBLRadianceLambertian's (its bias not weighted)
    const float ems = 1.0f - (fa + fb);
    const float favg = sw * (f0l[c] + (1.0f - f0l[c]) / 21.0f);
    const float fms_ems = ems * fss_ess * favg / (1.0f - favg * ems);
    const float kd = cd[c] * (1.0f - fss_ess + fms_ems);
    out[c] = sw * light[c] * (ks * fa + fb) + (fms_ems + kd) * irr[c];  // getIBLRadianceGGX's
  }
}

Rgb SplitSum::shade(const Vec3& nd, const Vec3& vd, const PreviewMaterial& m, float normal_slope2) const {
  BaseInputs in;
  // getAARoughnessFactors (pbrBRDFFunctions.fx): geometricAlphaGFactor = 0.75 sqrt(slopeSquare)
  in.aa_alpha_g = specular_aa_ ? 0.75f * std::sqrt(std::max(normal_slope2, 0.0f)) : 0.0f;
  const Rgb f0d = preview_f0(m), cdd = preview_diffuse_color(m);
  in.f0[0] = float(f0d.r), in.f0[1] = float(f0d.g), in.f0[2] = float(f0d.b);  // generic and Babylon.js mix in the film
  in.cd[0] = float(cdd.r), in.cd[1] = float(cdd.g), in.cd[2] = float(cdd.b);
  in.f90 = float(preview_f90(m)), in.specular = float(m.specular);
  in.nx = float(nd.x), in.ny = float(nd.y), in.nz = float(nd.z), in.vx = float(vd.x), in.vy = float(vd.y),
  in.vz = float(vd.z);
  in.dot_nv = in.nx * in.vx + in.ny * in.vy + in.nz * in.vz;
  in.levels_minus_one = float(levels_.size() - 1);
  float out[3] = {0, 0, 0};
  diffuse(nd, in.irr);
  switch (files_.target) {
    case EngineTarget::Generic:
      base_generic(m, in, out);
      break;
    case EngineTarget::Filament:
      base_filament(m, in, out);
      break;
    case EngineTarget::Gltf:
    case EngineTarget::Babylon:
      base_babylon(m, in, out);
      break;
    case EngineTarget::KhronosViewer:
      base_khronos_viewer(m, in, out);
      break;
  }
  if (preview_has_sheen(m) && renders_sheen()) sheen(nd, vd, m, in.aa_alpha_g, out);
  if (m.clearcoat > 0.0) coat(nd, vd, m, in.aa_alpha_g, out);
  if (files_.target == EngineTarget::Gltf || files_.target == EngineTarget::Babylon)
    for (float& o : out) o = std::max(o, 0.0f);  // pbrBlockFinalColorComposition.fx: max(finalColor, 0)
  return {out[0], out[1], out[2]};
}

bool SplitSum::renders_sheen() const {
  switch (files_.target) {
    case EngineTarget::Filament:
      return true;  // the GGX chain at the sheen's LOD, its own table's sheen channel
    case EngineTarget::Gltf:
    case EngineTarget::Babylon:
      return files_.charlie.width > 0;  // the GGX chain at the sheen's LOD, the charlie table
    case EngineTarget::Generic:
    case EngineTarget::KhronosViewer:
      return files_.charlie.width > 0 && !sheen_levels_.empty();
  }
  return false;
}

std::string SplitSum::sheen_note() const {
  if (!renders_sheen()) {
    return std::string("KHR_materials_sheen: not in the split-sum render (the bake has no ") +
           (files_.charlie.width == 0 ? "charlie DFG table" : "Charlie chain") +
           ": bake from the scene's materials, bake --scene); in the reference";
  }
  auto name = [](const std::string& path) { return std::filesystem::path(path).filename().string(); };
  const std::string table = " x E(n.v, sheenRoughness) of " + name(files_.charlie_file);
  switch (files_.target) {
    case EngineTarget::Generic:
      return "KHR_materials_sheen: in the split-sum render, docs/CONVENTIONS.md's runtime: sheenColor x " +
             name(files_.sheen_file) + " at lod (levels - 1) sheenRoughness" + table +
             ", the base x max(1 - max(sheenColor) E, 0)";
    case EngineTarget::KhronosViewer:
      return "KHR_materials_sheen: in the split-sum render, the glTF-Sample-Viewer's getIBLRadianceCharlie (" +
             name(files_.sheen_file) + " at lod sheenRoughness (mips - 1)" + table +
             " x sheenColor) and albedoSheenScaling 1 - max3(sheenColor) E";
    case EngineTarget::Filament:
      return "KHR_materials_sheen: in the split-sum render, Filament's evaluateSheenIBL (the GGX chain at "
             "perceptualRoughnessToLod(sheenPerceptualRoughness) x sheenDFG, the z channel of Filament's built-in "
             "DFG table at (n.v, sheenPerceptualRoughness), x sheenColor; Fd and Fr x 1 - max3(sheenColor) sheenDFG)";
    case EngineTarget::Gltf:
    case EngineTarget::Babylon:
      return "KHR_materials_sheen: in the split-sum render, Babylon.js's sheen block (pbrBlockSheen.fx, the glTF "
             "loader's albedoScaling): the reflection texture at getLodFromAlphaG(sheenRoughness^2 + 0.0005) x "
             "sheenColor x b, the base x 1 - max(sheenColor) b, b = the BRDF lookup's sheen channel at (n.v, "
             "sheenRoughness), here E(n.v, sheenRoughness) of " +
             name(files_.charlie_file) + " (" +
             (files_.charlie_visibility.empty() ? std::string("its") : files_.charlie_visibility) +
             " visibility; Babylon.js's own BRDF texture's blue channel integrates Ashikhmin's, 1 / (4 (n.l + n.v - "
             "n.l n.v)), "
             "which a charlie table of sheen_visibility neubelt holds)";
  }
  return {};
}

void SplitSum::sheen(const Vec3& nd, const Vec3& vd, const PreviewMaterial& m, float aa_alpha_g, float out[3]) const {
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float c[3] = {float(m.sheen_color.r), float(m.sheen_color.g), float(m.sheen_color.b)};
  const float cmax = std::max(c[0], std::max(c[1], c[2]));
  float light[3];
  switch (files_.target) {
    case EngineTarget::Generic: {
      // docs/CONVENTIONS.md, "Charlie sheen at run time": sheen = sheenColor x prefiltered Charlie
      // radiance (lod (levels - 1) sheenRoughness, the linear schedule) x E(n.v, sheenRoughness); the
      // base scaled by max(1 - max(sheenColor) E, 0)
      const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.sheen_roughness);
      trilinear_in(sheen_levels_, refl, float(sheen_levels_.size() - 1) * r, light);
      const float e = charlie(nv, r), scale = std::max(1.0f - cmax * e, 0.0f);
      for (int k = 0; k < 3; ++k) out[k] = out[k] * scale + c[k] * light[k] * e;
      return;
    }
    case EngineTarget::KhronosViewer: {
      // ibl.glsl getIBLRadianceCharlie: lod = sheenRoughness (u_MipCount - 1) on the Charlie chain at
      // normalize(reflect(-v, n)), times the charlie LUT at clamp((NdotV, sheenRoughness)), times
      // sheenColor; pbr.frag: color = f_sheen + color albedoSheenScaling, albedoSheenScaling = 1 -
      // max3(sheenColor) albedoSheenScalingLUT(NdotV, sheenRoughness) (not clamped); both LUTs are the
      // bake's charlie table
      const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = std::clamp(float(m.sheen_roughness), 0.0f, 1.0f);
      // (u_MipCount is the GGX chain's: the IBL Sampler writes both chains with the same levels)
      trilinear_in(sheen_levels_, refl, r * float(levels_.size() - 1), light);
      const float e = charlie(nv, r), scale = 1.0f - cmax * e;
      for (int k = 0; k < 3; ++k) out[k] = c[k] * light[k] * e + out[k] * scale;
      return;
    }
    case EngineTarget::Filament: {
      // light_indirect.fs evaluateSheenIBL: Fd and Fr times sheenScaling = 1 - max3(sheenColor)
      // sheenDFG; Fr += sheenDFG sheenColor prefilteredRadiance(shading_reflected,
      // sheenPerceptualRoughness): the GGX chain at perceptualRoughnessToLod; sheenDFG =
      // prefilteredDFG(sheenPerceptualRoughness, NoV).z, Filament's built-in table's third channel;
      // sheenPerceptualRoughness clamped to [MIN_PERCEPTUAL_ROUGHNESS 0.045, 1] (common_material.fs)
      const float nv = std::max(dot_nv, 1e-4f);
      const float pr = std::clamp(float(m.sheen_roughness), 0.045f, 1.0f);
      const float e = charlie(nv, pr), scale = 1.0f - cmax * e;
      trilinear(refl, float(levels_.size() - 1) * pr * (2.0f - pr), light);
      for (int k = 0; k < 3; ++k) out[k] = out[k] * scale + e * c[k] * light[k];
      return;
    }
    case EngineTarget::Gltf:
    case EngineTarget::Babylon: {
      // pbrBlockSheen.fx, sheenBlock (SHEEN_ROUGHNESS, SHEEN_ALBEDOSCALING; sheen.intensity 1 from the
      // glTF loader): the reflection texture at reflectionCoords (the base's) and the sheen's alphaG,
      // times sheenColor x environmentSheenBrdf.b, environmentSheenBrdf = getBRDFLookup(NdotV,
      // sheenRoughness) (NdotV the base's absEps); pbrBlockFinalLitComponents.fx: surfaceAlbedo and
      // finalRadianceScaled times sheenAlbedoScaling. b is the charlie table's E (sheen_note)
      const float nv = babylon::abs_eps(dot_nv), r = float(m.sheen_roughness);
      // sheenAlphaG += AARoughnessFactors.y under SPECULARAA
      reflection(refl,
                 babylon::reflection_lod(float(files_.specular.size), babylon::alpha_g(r) + aa_alpha_g,
                                         float(files_.lod_scale)),
                 light);
      const babylon::Sheen s = babylon::sheen(c, 1.0f, charlie(nv, r));
      for (int k = 0; k < 3; ++k) out[k] = out[k] * s.albedo_scaling + light[k] * s.reflectance[k];
      return;
    }
  }
}

void SplitSum::coat(const Vec3& nd, const Vec3& vd, const PreviewMaterial& m, float aa_alpha_g, float out[3]) const {
  // KHR_materials_clearcoat with the geometric normal (the sphere's): each target's layering of a
  // second GGX lobe over the base it has shaded into `out`
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float levels_minus_one = float(levels_.size() - 1), cc = float(m.clearcoat);
  float light[3];
  switch (files_.target) {
    case EngineTarget::Generic: {
      // the extension's fresnel_coat over the split sum: the coat's radiance is prefiltered x A_coat
      // (its layer D V carries no Fresnel), weighted by clearcoat Fcoat(n.v), Fcoat = F_Schlick(0.04, 1)
      const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.clearcoat_roughness);
      float bias = 0, albedo = 0;
      trilinear(refl, levels_minus_one * r, light);
      dfg(nv, r, &bias, &albedo);
      const float t = cc * (0.04f + 0.96f * pow5(1.0f - nv));
      for (int c = 0; c < 3; ++c) out[c] = out[c] * (1.0f - t) + t * light[c] * albedo;
      return;
    }
    case EngineTarget::Filament: {
      // light_indirect.fs, evaluateClearCoatIBL (no clear coat normal: clearCoatNoV = shading_NoV,
      // clearCoatR = shading_reflected): Fc = F_Schlick(0.04, 1, NoV) clearCoat; Fd and Fr times
      // 1 - Fc; Fr += prefilteredRadiance(clearCoatR, clearCoatPerceptualRoughness) Fc (no DFG term);
      // clearCoatPerceptualRoughness clamped to [MIN_PERCEPTUAL_ROUGHNESS, 1] (common_material.fs)
      const float nv = std::max(dot_nv, 1e-4f);
      const float pr = std::clamp(float(m.clearcoat_roughness), 0.045f, 1.0f);
      trilinear(refl, levels_minus_one * pr * (2.0f - pr), light);
      const float fc = (0.04f + 0.96f * pow5(1.0f - std::min(nv, 1.0f))) * cc;
      for (int c = 0; c < 3; ++c) out[c] = out[c] * (1.0f - fc) + light[c] * fc;
      return;
    }
    case EngineTarget::KhronosViewer: {
      // pbr.frag: f_clearcoat = getIBLRadianceGGX(clearcoatNormal, v, clearcoatRoughness, clearcoatF0, 1)
      // (ibl.glsl), clearcoatFresnel = F_Schlick(clearcoatF0, 1, NdotV), color = color (1 - clearcoatFactor
      // clearcoatFresnel) + clearcoatFactor f_clearcoat; material_info.glsl getClearCoatInfo: clearcoatF0 =
      // the material's f0 at that point, mix(f0 of the ior, baseColor, metallic)
      PreviewMaterial plain = m;
      plain.specular = 1.0;
      plain.specular_color = {1.0, 1.0, 1.0};
      const Rgb f0d = preview_f0(plain);
      const float f0[3] = {float(f0d.r), float(f0d.g), float(f0d.b)};
      const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.clearcoat_roughness);
      float bias = 0, albedo = 0;
      trilinear(refl, r * levels_minus_one, light);
      dfg(nv, std::clamp(r, 0.0f, 1.0f), &bias, &albedo);
      const float fa = albedo - bias, fb = bias;
      for (int c = 0; c < 3; ++c) {
        const float fr = std::max(1.0f - r, f0[c]) - f0[c];
        const float ks = f0[c] + fr * pow5(1.0f - nv);
        const float fresnel = f0[c] + (1.0f - f0[c]) * pow5(1.0f - nv);
        out[c] = out[c] * (1.0f - cc * fresnel) + cc * light[c] * (ks * fa + fb);
      }
      return;
    }
    case EngineTarget::Gltf:
    case EngineTarget::Babylon: {
      // pbrBlockClearcoat.fx, clearcoatBlock (the glTF loader: remapF0OnInterfaceChange false, so the
      // base's R0 stays; no tint, no bump: clearCoatNormalW = the geometric normal): the reflection
      // texture at the coat's alphaG along computeReflectionCoords (the base's direction), times
      // getReflectanceFromBRDFLookup(0.04, getBRDFLookup(clearCoatNdotV, clearCoatRoughness)) x
      // intensity; the base (irradiance, radiance) and the sheen's radiance times conservationFactor
      // (pbrBlockReflectance.fx, pbrBlockFinalLitComponents.fx)
      const float nv = babylon::abs_eps(dot_nv), r = float(m.clearcoat_roughness);
      // clearCoatAlphaG += clearCoatAARoughnessFactors.y under SPECULARAA (the same normal here)
      reflection(refl,
                 babylon::reflection_lod(float(files_.specular.size), babylon::alpha_g(r) + aa_alpha_g,
                                         float(files_.lod_scale)),
                 light);
      float x = 0, y = 0;
      dfg(nv, r, &x, &y);  // height-correlated: (bias, albedo), as the base's lookup
      const babylon::ClearCoat k = babylon::clear_coat(cc, nv, x, y);
      for (int c = 0; c < 3; ++c) out[c] = out[c] * k.conservation + light[c] * k.coat_reflectance;
      return;
    }
  }
}

Metadata SplitSum::steps() const {
  const std::string lut = "the bake's DFG table (" + files_.dfg_file + ", " + std::to_string(files_.dfg.width) + "x" +
                          std::to_string(files_.dfg.height) + "), bilinear, clamp to edge, texel centres";
  const std::string cube = "trilinear, seamless (OpenGL 4.6 8.13.1), on " + files_.specular_file + " decoded from " +
                           files_.specular_format + ", " + std::to_string(files_.specular.level_count()) + " levels";
  switch (files_.target) {
    case EngineTarget::Generic:
      return {{"lod", "(levels - 1) roughness (docs/CONVENTIONS.md, linear schedule)"},
              {"specular_sample", cube + ", at reflect(-v, n)"},
              {"dfg", lut + ", at (clamp(n.v), roughness)"},
              {"specular", files_.dfg_multiscatter ? "prefiltered x mix(bias, albedo, F0) x (1 + F0 (1 / albedo - 1))"
                                                   : "prefiltered x (F0 scale + bias)"},
              {"diffuse", "diffuse colour x sum c_lm Y_lm(n) (E / pi, " + files_.diffuse_file + ")"}};
    case EngineTarget::Filament:
      return {
          {"roughness",
           "clamp(roughness, MIN_PERCEPTUAL_ROUGHNESS 0.045, 1) (common_material.fs); n.v = clampNoV: max(n.v, 1e-4)"},
          {"lod", "perceptualRoughnessToLod: (levels - 1) r (2 - r) (light_indirect.fs)"},
          {"direction",
           "getSpecularDominantDirection: mix(reflect(-v, n), n, roughness^2), roughness = r^2 (light_indirect.fs)"},
          {"specular_sample", cube + " (prefilteredRadiance)"},
          {"dfg", lut + " (PrefilteredDFG_LUT(perceptualRoughness, NoV)): Filament 1.76 samples the table built "
                        "into it, never the bake's"},
          {"specular",
           "specularDFG: mix(dfg.x, dfg.y, F0) x prefilteredRadiance x energyCompensation 1 + F0 (1 / dfg.y - 1) "
           "(evaluateIBL)"},
          {"diffuse",
           "diffuseColor x Irradiance_SphericalHarmonics(n) (max(sum sh_k poly_k, 0), the KTX sh key) x (1 - E) "
           "(evaluateIBL)"}};
    case EngineTarget::Gltf:
    case EngineTarget::Babylon: {
      const bool gltf = files_.target == EngineTarget::Gltf;
      Metadata m = {
          {"engine", "Babylon.js 8.46.2 defaults (PBRMaterial; the glTF loader's materials for gltf)"},
          {"frame", gltf ? std::string("EXT_lights_image_based in Babylon.js's ") +
                               (files_.gltf_scene == GltfScene::LeftHanded
                                    ? "default left-handed scene: the loader mirrors the glTF content in x, not the "
                                      "cube (the file stores it mirrored, rotation identity)"
                                    : "right-handed scene: every cube turned 180 degrees about +Y, undone by the "
                                      "light's rotation (0, 1, 0, 0)")
                         : std::string("the .env's cube as stored")},
          {"alpha_g", std::string("convertRoughnessToAverageSlope: roughness^2 + 0.0005") +
                          (gltf ? " + 0.75 sqrt(max(|dFdx n|^2, |dFdy n|^2)) (SPECULARAA: the loader's "
                                  "enableSpecularAntiAliasing; coarse derivatives of the analytic normal over each 2 x "
                                  "2 pixel quad)"
                                : "")},
          {"lod", "getLodFromAlphaG: log2(size alphaG) x lodGenerationScale " + std::to_string(files_.lod_scale) +
                      (gltf ? " ((N - 1) / log2 size, EXT_lights_image_based.ts)" : " (the .env's)") +
                      " (pbrBlockReflection.fx, sampleReflectionTexture)"},
          {"specular_sample",
           cube +
               ", faces read bottom row first, RGBD expanded to half float (environmentTextureTools.ts, "
               "_UploadLevelsAsync)" +
               (gltf ? std::string(", then toLinearSpace (x^2.2): the loader's RawCubeTexture keeps gammaSpace true "
                                   "(GAMMAREFLECTION), so every reflection sample is decoded a second time")
                     : std::string())},
          {"mix_ibl_radiance_with_irradiance",
           options_.babylon_mix_ibl_radiance_with_irradiance
               ? "on (PBRBRDFConfiguration.DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE): environmentRadiance = "
                 "mix(environmentRadiance, environmentIrradiance, alphaG) (reflectionBlock)"
               : "off (--no-mix-ibl-radiance-with-irradiance)"},
          {"dfg", lut + " (pbrBRDFFunctions.fx, getBRDFLookup(NdotV = |n.v| + 1e-7, roughness))"},
          {"specular",
           "getReflectanceFromBRDFLookup: (R90 - R0) x + R0 y, R90 = specularWeight (specularFactor: "
           "LEGACY_SPECULAR_ENERGY_CONSERVATION's reflectanceF90), x getEnergyConservationFactor 1 + R0 (1 / y - 1) "
           "(pbrBlockFinalLitComponents.fx)"},
          {"diffuse",
           std::string("surfaceAlbedo x environmentIrradiance (") +
               (gltf ? "irradianceCoefficients / pi, SphericalHarmonics" : "the .env's spherical polynomial") +
               ", computeEnvironmentIrradiance); surfaceAlbedo = baseColor (1 - dielectricF0 "
               "specularColor) (1 - metallic), dielectricF0 = ((ior - 1) / (ior + 1))^2 specularFactor "
               "(LEGACY_SPECULAR_ENERGY_CONSERVATION, PBRBRDFConfiguration's default in 8.46.2)"}};
      return m;
    }
    case EngineTarget::KhronosViewer:
      return {{"lod", "roughness (u_MipCount - 1) (ibl.glsl, getIBLRadianceGGX)"},
              {"specular_sample", cube + ", at normalize(reflect(-v, n)) (getSpecularSample)"},
              {"dfg", lut + ", as f_ab = (scale, bias) at clamp(NdotV, roughness)"},
              {"specular",
               "specularLight x (k_S f_ab.x + f_ab.y), k_S = F0 + (max(1 - roughness, F0) - F0) (1 - NdotV)^5 "
               "(getIBLRadianceGGX)"},
              {"diffuse",
               "(FmsEms + k_D) x texture(u_LambertianEnvSampler, n) (getIBLRadianceLambertian, Fdez-Aguera's multiple "
               "scattering)"}};
  }
  return {};
}

}  // namespace brdfbake::detail::preview
