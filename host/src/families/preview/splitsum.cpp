// The split-sum render (splitsum.hpp): what every target shares (splitsum_sampling.hpp: the padded chains,
// textureLod, the tables' lookup, the diffuse term) and the calls into the target's own shading, its folder's
// host/src/engines/<target>/splitsum.cpp, found through the registry. The arithmetic is fp32, as in the shaders.
#include "families/preview/splitsum.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "brdfbake/error.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/sh.hpp"
#include "engines/registry.hpp"
#include "families/preview/iridescence.hpp"

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

// GL_LINEAR on one padded face of a level.
void sample_face(const PaddedLevel& lv, int face, float a, float b, float out[3]) {
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

// Padded levels of a cube (cube.clh's layout): each face (s + 2)^2 RGB texels, its border holding
// the neighbouring face's texel nearest to the extended texel centre, a corner the mean of the three
// texels around it: the seamless cube filtering of OpenGL 4.6, 8.13.1 (GL_TEXTURE_CUBE_MAP_SEAMLESS,
// always on in WebGL 2 and on in Filament).
PaddedLevel SplitSumSampler::pad(const CubeLevels& cube, int l) {
  PaddedLevel out;
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

void SplitSumSampler::bilinear(int level, const Vec3& d, float out[3]) const {
  float a = 0, b = 0;
  const int face = face_of(d, &a, &b);
  const PaddedChain& ls = level < 0 ? irradiance : levels;
  sample_face(ls[size_t(level < 0 ? 0 : level)], face, a, b, out);
}

void trilinear_in(const PaddedChain& chain, const Vec3& d, float lod, float out[3]) {
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

void SplitSumSampler::reflection(const Vec3& d, float lod, float out[3]) const {
  trilinear(d, lod, out);
  if (reflection_gamma)  // helperFunctions.fx toLinearSpace: pow(color, LinearEncodePowerApprox 2.2)
    for (int c = 0; c < 3; ++c) out[c] = std::pow(out[c], 2.2f);
}

void lut_lookup(const Table& t, bool sqrt_n_dot_v, float n_dot_v, float roughness, int channels, float* c, int first) {
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

float SplitSumSampler::charlie(float n_dot_v, float sheen_roughness) const {
  float e = 0.0f;
  lut_lookup(files.charlie, files.charlie_sqrt_n_dot_v, n_dot_v, sheen_roughness, 1, &e);
  return e;
}

void SplitSumSampler::dfg(float n_dot_v, float roughness, float* bias, float* albedo) const {
  float c[2];
  lut_lookup(files.dfg, files.dfg_sqrt_n_dot_v, n_dot_v, roughness, 2, c);
  if (files.dfg_multiscatter) {
    *bias = c[0];
    *albedo = c[1];
  } else {
    *bias = c[1];
    *albedo = c[0] + c[1];  // scale + bias
  }
}

void SplitSumSampler::diffuse(const Vec3& n, float out[3]) const {
  const std::vector<double>& c = files.sh;
  float p[9];
  poly9(float(n.x), float(n.y), float(n.z), p);
  switch (files.diffuse) {
    case DiffuseSource::OurSh: {
      // docs/CONVENTIONS.md: E(n) / pi = sum c_lm Y_lm(n)
      const std::vector<double> y = math::sh_basis(files.sh_order, n);
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
        for (size_t k = 0; k < 9; ++k) e += float(harmonics[3 * k + size_t(ch)]) * p[k];
        out[ch] = e;
      }
      return;
    case DiffuseSource::IrradianceCube: {
      // glTF-Sample-Viewer ibl.glsl, getDiffuseLight: texture(u_LambertianEnvSampler, n)
      bilinear(-1, n, out);
      return;
    }
    case DiffuseSource::None:
      out[0] = out[1] = out[2] = 0.0f;  // only for spheres without a diffuse lobe (render_preview)
      return;
  }
}

std::string SplitSumSampler::lut_text() const {
  return "the bake's DFG table (" + files.dfg_file + ", " + std::to_string(files.dfg.width) + "x" +
         std::to_string(files.dfg.height) + "), bilinear, clamp to edge, texel centres";
}

std::string SplitSumSampler::cube_text() const {
  return "trilinear, seamless (OpenGL 4.6 8.13.1), on " + files.specular_file + " decoded from " +
         files.specular_format + ", " + std::to_string(files.specular.level_count()) + " levels";
}

void iridescent_f0(const PreviewMaterial& m, float n_dot_v, float f0[3]) {
  float factor = 0.0f, fresnel[3];
  if (!split_sum_film(m, n_dot_v, f0, &factor, fresnel)) return;
  for (int c = 0; c < 3; ++c) f0[c] = f0[c] + (fresnel[c] - f0[c]) * factor;
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

SplitSum::SplitSum(BakeFiles files, SplitSumOptions options) : shading_(&engines::target_def(files.target).shading()) {
  sampler_.files = std::move(files);
  sampler_.options = options;
  const BakeFiles& f = sampler_.files;
  if (f.specular_levels.empty()) {
    for (int l = 0; l < f.specular.level_count(); ++l) sampler_.levels.push_back(SplitSumSampler::pad(f.specular, l));
  } else {
    if (int(f.specular_levels.size()) != f.specular.level_count())
      throw Error("the ideal bake's chain has " + std::to_string(f.specular_levels.size()) + " levels, not " +
                  std::to_string(f.specular.level_count()));
    for (const CubeLevels& level : f.specular_levels) sampler_.levels.push_back(SplitSumSampler::pad(level, 0));
  }
  if (!f.irradiance.levels.empty()) sampler_.irradiance.push_back(SplitSumSampler::pad(f.irradiance, 0));
  if (f.sheen_levels.empty()) {
    for (int l = 0; l < f.sheen.level_count(); ++l) sampler_.sheen_levels.push_back(SplitSumSampler::pad(f.sheen, l));
  } else {
    if (int(f.sheen_levels.size()) != f.sheen.level_count())
      throw Error("the ideal bake's Charlie chain has " + std::to_string(f.sheen_levels.size()) + " levels, not " +
                  std::to_string(f.sheen.level_count()));
    for (const CubeLevels& level : f.sheen_levels) sampler_.sheen_levels.push_back(SplitSumSampler::pad(level, 0));
  }
  if (shading_->prepare) shading_->prepare(sampler_);
  // The GGX chain is sampled from its padded copies: its unpadded texels are let go, the levels' count
  // and sizes kept (what the engine's lookup reads; an ideal bake made from these files replaces the
  // chain and reads only those). The memory of the preview and the bake sweep: a 512^2 chain and its
  // ideal bake's are ~200 MB. The Charlie chain likewise (an ideal bake made from these files
  // replaces it too); the irradiance cube stays: an ideal bake keeps the files' own.
  for (std::vector<float>& level : sampler_.files.specular.levels) std::vector<float>().swap(level);
  std::vector<CubeLevels>().swap(sampler_.files.specular_levels);
  for (std::vector<float>& level : sampler_.files.sheen.levels) std::vector<float>().swap(level);
  std::vector<CubeLevels>().swap(sampler_.files.sheen_levels);
  if (f.diffuse == DiffuseSource::OurSh && f.sh_order < 3)
    throw Error("'" + f.diffuse_file + "': SH of " + std::to_string(f.sh_order) + " bands (at least 3)");
}

Rgb SplitSum::sky(const Vec3& d) const {
  float o[3];
  sampler_.bilinear(0, d, o);
  return {o[0], o[1], o[2]};
}

Rgb SplitSum::shade(const Vec3& nd, const Vec3& vd, const PreviewMaterial& m, float normal_slope2) const {
  BaseInputs in;
  // getAARoughnessFactors (pbrBRDFFunctions.fx): geometricAlphaGFactor = 0.75 sqrt(slopeSquare)
  in.aa_alpha_g = sampler_.specular_aa ? 0.75f * std::sqrt(std::max(normal_slope2, 0.0f)) : 0.0f;
  const Rgb f0d = preview_f0(m), cdd = preview_diffuse_color(m);
  in.f0[0] = float(f0d.r), in.f0[1] = float(f0d.g), in.f0[2] = float(f0d.b);  // generic and Babylon.js mix in the film
  in.cd[0] = float(cdd.r), in.cd[1] = float(cdd.g), in.cd[2] = float(cdd.b);
  in.f90 = float(preview_f90(m)), in.specular = float(m.specular);
  in.nx = float(nd.x), in.ny = float(nd.y), in.nz = float(nd.z), in.vx = float(vd.x), in.vy = float(vd.y),
  in.vz = float(vd.z);
  in.dot_nv = in.nx * in.vx + in.ny * in.vy + in.nz * in.vz;
  in.levels_minus_one = float(sampler_.levels.size() - 1);
  float out[3] = {0, 0, 0};
  sampler_.diffuse(nd, in.irr);
  shading_->base(sampler_, m, in, out);
  if (preview_has_sheen(m) && renders_sheen()) shading_->sheen(sampler_, nd, vd, m, in.aa_alpha_g, out);
  if (m.clearcoat > 0.0) shading_->coat(sampler_, nd, vd, m, in.aa_alpha_g, out);
  if (shading_->clamp_at_zero)
    for (float& o : out) o = std::max(o, 0.0f);  // pbrBlockFinalColorComposition.fx: max(finalColor, 0)
  return {out[0], out[1], out[2]};
}

bool SplitSum::renders_sheen() const { return shading_->renders_sheen(sampler_); }

std::string SplitSum::sheen_note() const {
  if (!renders_sheen()) {
    return std::string("KHR_materials_sheen: not in the split-sum render (the bake has no ") +
           (sampler_.files.charlie.width == 0 ? "charlie DFG table" : "Charlie chain") +
           ": bake from the scene's materials, bake --scene); in the reference";
  }
  return shading_->sheen_note(sampler_);
}

Metadata SplitSum::steps() const { return shading_->steps(sampler_); }

}  // namespace brdfbake::detail::preview
