// Bulk BRDF evaluation and tabulation on the device (kernels/brdf_eval.cl): names, lobes, the
// materials' parameter blocks (derived here, by the engine's own code), programs, evaluation and
// tables. The reference backend (eval_reference, tabulate_reference, tabulate_merl_reference) is
// host/src/reference_backend/brdf.cpp.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "brdf_eval_internal.hpp"
#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/gauss_legendre.hpp"
#include "brdfbake/version.hpp"
#include "runtime/program.hpp"
#include "sheen_albedo.hpp"

// The parameter block layout, shared with the kernels.
#include "../../kernels/common/brdf_params.clh"

namespace brdfbake {
namespace {

using math::kDisneyMinAlpha;
using math::kMinAlpha;
using math::kPi;
constexpr double kHalfPi = 0.5 * kPi;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// ---- Names ----------------------------------------------------------------------------------------

struct ModelName {
  BrdfModel model;
  const char* name;
  const char* define;
};
const ModelName kModels[] = {
    {BrdfModel::Disney, "disney", "BRDFBAKE_MODEL_DISNEY"},
    {BrdfModel::Gltf, "gltf", "BRDFBAKE_MODEL_GLTF"},
    {BrdfModel::GltfCorrelated, "gltf-correlated", "BRDFBAKE_MODEL_GLTF_CORRELATED"},
    {BrdfModel::Lambert, "lambert", "BRDFBAKE_MODEL_LAMBERT"},
    {BrdfModel::Phong, "phong", "BRDFBAKE_MODEL_PHONG"},
    {BrdfModel::BlinnPhong, "blinn-phong", "BRDFBAKE_MODEL_BLINN_PHONG"},
    {BrdfModel::CookTorrance, "cook-torrance", "BRDFBAKE_MODEL_COOK_TORRANCE"},
    {BrdfModel::BlinnPhongFromPbr, "blinn-phong-from-pbr", "BRDFBAKE_MODEL_BLINN_PHONG_FROM_PBR"},
};

const ModelName& model_entry(BrdfModel model) {
  for (const ModelName& m : kModels)
    if (m.model == model) return m;
  throw Error("unknown BRDF model");
}

bool is_gltf(BrdfModel m) { return m == BrdfModel::Gltf || m == BrdfModel::GltfCorrelated; }

const char* kLayoutNames[] = {"merl", "grid", "albedo", "slice"};

double max3(const Rgb& c) { return std::max(c.r, std::max(c.g, c.b)); }
double mix(double a, double b, double t) { return a + (b - a) * t; }

// ---- Material set-up: the parameter block of common/brdf_params.clh ------------------------------
// Everything per material (tints, Fresnel indices, widths, normalisations) is derived here in double,
// once, from the parameters as the papers define them (cited in kernels/brdf_eval.cl).
using Block = std::array<double, BRDF_PARAM_STRIDE>;

void put(Block& b, int slot, const Rgb& c) {
  b[static_cast<size_t>(slot)] = c.r;
  b[static_cast<size_t>(slot) + 1] = c.g;
  b[static_cast<size_t>(slot) + 2] = c.b;
}
void put(Block& b, int slot, double v) { b[static_cast<size_t>(slot)] = v; }
Rgb scale(const Rgb& c, double s) { return {c.r * s, c.g * s, c.b * s}; }

// The classic models' parameter conventions (docs/CONVENTIONS.md): kd = diffuse_color, else
// base_color (1 - metallic); ks = specular_color, else mix(0.04, base_color, metallic) (the
// metallic-roughness F0); n = shininess, else 2048^(1 - roughness) (blinn-phong-from-pbr's mapping).
Rgb classic_kd(const Material& m) { return m.diffuse_color ? *m.diffuse_color : scale(m.base_color, 1.0 - m.metallic); }
Rgb classic_ks(const Material& m) {
  if (m.specular_color) return *m.specular_color;
  const Rgb& c = m.base_color;
  return {mix(0.04, c.r, m.metallic), mix(0.04, c.g, m.metallic), mix(0.04, c.b, m.metallic)};
}
double classic_exponent(const Material& m) { return m.shininess ? *m.shininess : std::pow(2048.0, 1.0 - m.roughness); }

Block pack_material(BrdfModel model, const Material& m, double sheen_table_offset) {
  Block b{};
  const double r2 = m.roughness * m.roughness;
  switch (model) {
    case BrdfModel::Disney: {
      // disney.brdf: Ctint = C / lum(C) (1 when lum = 0), Cspec0 = mix(0.08 specular mix(1, Ctint,
      // specularTint), C, metallic), Csheen = mix(1, Ctint, sheenTint).
      const Rgb c = m.base_color;
      const double lum = 0.3 * c.r + 0.6 * c.g + 0.1 * c.b;
      const Rgb tint = lum > 0.0 ? scale(c, 1.0 / lum) : Rgb{1.0, 1.0, 1.0};
      auto tinted = [&](double t) {
        return Rgb{mix(1.0, tint.r, t), mix(1.0, tint.g, t), mix(1.0, tint.b, t)};
      };
      const Rgb s = scale(tinted(m.specular_tint), 0.08 * m.specular);
      put(b, BRDF_DISNEY_KD, scale(c, (1.0 - m.metallic) / kPi));
      put(b, BRDF_DISNEY_SPEC0, Rgb{mix(s.r, c.r, m.metallic), mix(s.g, c.g, m.metallic), mix(s.b, c.b, m.metallic)});
      put(b, BRDF_DISNEY_SHEEN, scale(tinted(m.sheen_tint), m.sheen * (1.0 - m.metallic)));
      put(b, BRDF_DISNEY_ROUGHNESS, m.roughness);
      put(b, BRDF_DISNEY_SUBSURFACE, m.subsurface);
      const double aspect = std::sqrt(1.0 - 0.9 * m.anisotropic);
      const double ax = std::max(kDisneyMinAlpha, r2 / aspect);
      const double ay = std::max(kDisneyMinAlpha, r2 * aspect);
      put(b, BRDF_DISNEY_AX, ax);
      put(b, BRDF_DISNEY_AY, ay);
      put(b, BRDF_DISNEY_D_NORM, 1.0 / (kPi * ax * ay));
      // GTR1 at a = mix(0.1, 0.001, clearcoatGloss): (a^2 - 1) / (pi ln a^2)
      const double a = mix(0.1, 0.001, m.clearcoat_gloss), a2 = a * a;
      put(b, BRDF_DISNEY_COAT, 0.25 * m.clearcoat);
      put(b, BRDF_DISNEY_COAT_A2, a2);
      put(b, BRDF_DISNEY_COAT_NORM, (a2 - 1.0) / (kPi * std::log(a2)));
      break;
    }
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated: {
      const Rgb c = m.base_color;
      // fresnel_mix with KHR_materials_ior and _specular: f0 = min(((1 - ior)/(1 + ior))^2 f0_color, 1)
      const double q = (1.0 - m.ior) / (1.0 + m.ior), f0_ior = q * q;
      const Rgb f0{std::min(f0_ior * m.specular_color_factor.r, 1.0), std::min(f0_ior * m.specular_color_factor.g, 1.0),
                   std::min(f0_ior * m.specular_color_factor.b, 1.0)};
      put(b, BRDF_GLTF_KD, scale(c, (1.0 - m.metallic) / kPi));
      put(b, BRDF_GLTF_F0, f0);
      put(b, BRDF_GLTF_METAL_F0, c);
      put(b, BRDF_GLTF_WEIGHT, m.specular_factor);
      put(b, BRDF_GLTF_DIELECTRIC, (1.0 - m.metallic) * m.specular_factor);
      put(b, BRDF_GLTF_METALLIC, m.metallic);
      const double alpha = std::max(r2, kMinAlpha);
      put(b, BRDF_GLTF_A2, alpha * alpha);
      const double alpha_s = m.sheen_roughness * m.sheen_roughness;
      const double inv_a = 1.0 / std::max(alpha_s, kMinAlpha);
      put(b, BRDF_GLTF_SHEEN, m.sheen_color);
      put(b, BRDF_GLTF_SHEEN_MAX, max3(m.sheen_color));
      put(b, BRDF_GLTF_SHEEN_INV_A, inv_a);
      put(b, BRDF_GLTF_SHEEN_NORM, (2.0 + inv_a) / (2.0 * kPi));
      const detail::EstevezKullaFit fit = detail::estevez_kulla_fit(alpha_s);
      put(b, BRDF_GLTF_SHEEN_FIT + 0, fit.a);
      put(b, BRDF_GLTF_SHEEN_FIT + 1, fit.b);
      put(b, BRDF_GLTF_SHEEN_FIT + 2, fit.c);
      put(b, BRDF_GLTF_SHEEN_FIT + 3, fit.d);
      put(b, BRDF_GLTF_SHEEN_FIT + 4, fit.e);
      put(b, BRDF_GLTF_SHEEN_L_HALF, fit.a / (1.0 + fit.b * std::pow(0.5, fit.c)) + 0.5 * fit.d + fit.e);
      put(b, BRDF_GLTF_SHEEN_TABLE, sheen_table_offset);
      put(b, BRDF_GLTF_SHEEN_S_SEAM, std::pow(0.5, fit.c));
      put(b, BRDF_GLTF_F0_MAX, max3(f0));
      const double alpha_c = std::max(m.clearcoat_roughness * m.clearcoat_roughness, kMinAlpha);
      put(b, BRDF_GLTF_COAT, m.clearcoat);
      put(b, BRDF_GLTF_COAT_A2, alpha_c * alpha_c);
      break;
    }
    case BrdfModel::Lambert:
      put(b, BRDF_CLASSIC_KD, scale(classic_kd(m), 1.0 / kPi));
      break;
    case BrdfModel::Phong:
    case BrdfModel::BlinnPhong: {
      const double n = classic_exponent(m);
      // Lewis 1994: (n + 2) / (2 pi); RTR3 eq. 7.49: (n + 8) / (8 pi)
      const double norm = !m.normalized ? 1.0 : model == BrdfModel::Phong ? (n + 2.0) / (2.0 * kPi) : (n + 8.0) / (8.0 * kPi);
      put(b, BRDF_CLASSIC_KD, scale(classic_kd(m), 1.0 / kPi));
      put(b, BRDF_CLASSIC_KS, scale(classic_ks(m), norm));
      put(b, BRDF_CLASSIC_N, n);
      break;
    }
    case BrdfModel::CookTorrance: {
      put(b, BRDF_CLASSIC_KD, scale(classic_kd(m), 1.0 / kPi));
      // eta = (1 + sqrt F0) / (1 - sqrt F0); F0 = 1 (eta infinite) -> -1.
      const Rgb f0 = classic_ks(m);
      for (int c = 0; c < 3; ++c) {
        const double v = c == 0 ? f0.r : c == 1 ? f0.g : f0.b;
        const double s = std::sqrt(v);
        put(b, BRDF_CLASSIC_KS + c, v >= 1.0 ? -1.0 : (1.0 + s) / (1.0 - s));
      }
      const double alpha = std::max(r2, kMinAlpha);
      put(b, BRDF_CLASSIC_A2, alpha * alpha);
      put(b, BRDF_CLASSIC_BECKMANN, m.distribution == MicrofacetDistribution::Beckmann ? 1.0 : 0.0);
      break;
    }
    case BrdfModel::BlinnPhongFromPbr: {
      const double n = std::pow(2048.0, 1.0 - m.roughness);
      const Rgb c = m.base_color;
      put(b, BRDF_CLASSIC_KD, scale(c, (1.0 - m.metallic) / kPi));
      put(b, BRDF_CLASSIC_KS, Rgb{mix(0.04, c.r, m.metallic), mix(0.04, c.g, m.metallic), mix(0.04, c.b, m.metallic)});
      put(b, BRDF_CLASSIC_N, n);
      put(b, BRDF_CLASSIC_NORM, (n + 8.0) / (8.0 * kPi));
      break;
    }
  }
  return b;
}

bool has_sheen(BrdfModel model, const Material& m) { return is_gltf(model) && max3(m.sheen_color) > 0.0; }

// The narrowest lobe of a material, in radians of the half vector's polar angle: the albedo
// quadrature starts its log-spaced polar nodes 1e-4 of it below it.
double narrowest_lobe(BrdfModel model, const Material& m) {
  const double r2 = std::max(m.roughness * m.roughness, kMinAlpha);
  switch (model) {
    case BrdfModel::Disney: {
      const double aspect = std::sqrt(1.0 - 0.9 * m.anisotropic);
      double w = std::max(kDisneyMinAlpha, r2 * aspect);
      if (m.clearcoat > 0.0) w = std::min(w, mix(0.1, 0.001, m.clearcoat_gloss));
      return w;
    }
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated:
      return m.clearcoat > 0.0 ? std::min(r2, std::max(m.clearcoat_roughness * m.clearcoat_roughness, kMinAlpha))
                               : r2;
    case BrdfModel::CookTorrance: return r2;
    case BrdfModel::Phong:
    case BrdfModel::BlinnPhong: return 1.0 / std::sqrt(classic_exponent(m) + 1.0);
    case BrdfModel::BlinnPhongFromPbr: return 1.0 / std::sqrt(std::pow(2048.0, 1.0 - m.roughness) + 1.0);
    case BrdfModel::Lambert: break;
  }
  return 1.0;
}

// ---- Programs -------------------------------------------------------------------------------------

// Lane widths measured by bench/brdf_bench on PoCL (docs/BENCHMARKS.md): float16 and double8 fill
// an AVX-512 register.
int default_lanes(Precision p) { return p == Precision::Fp64 ? 8 : 16; }

detail::ProgramSpec program_spec(BrdfModel model, const Lobes& lobes, const EvalOptions& options, int lanes) {
  detail::ProgramSpec ps;
  ps.file = "brdf_eval.cl";
  ps.precision = options.precision;
  ps.defines.push_back({model_entry(model).define, "1"});
  ps.defines.push_back({"BRDFBAKE_LANES", std::to_string(lanes)});
  const std::pair<bool, const char*> flags[] = {
      {lobes.diffuse, "BRDFBAKE_LOBE_DIFFUSE"},     {lobes.subsurface, "BRDFBAKE_LOBE_SUBSURFACE"},
      {lobes.sheen, "BRDFBAKE_LOBE_SHEEN"},         {lobes.clearcoat, "BRDFBAKE_LOBE_CLEARCOAT"},
      {lobes.anisotropic, "BRDFBAKE_LOBE_ANISOTROPIC"}, {lobes.metal, "BRDFBAKE_LOBE_METAL"},
      {lobes.specular_color, "BRDFBAKE_LOBE_SPECULAR_COLOR"}, {lobes.beckmann, "BRDFBAKE_CT_BECKMANN"},
      {lobes.ggx, "BRDFBAKE_CT_GGX"}};
  for (const auto& [on, name] : flags)
    if (on) ps.defines.push_back({name, "1"});
  if (options.fast_math) ps.options = "-cl-fast-relaxed-math";
  return ps;
}

int resolve_lanes(const EvalOptions& o) {
  const int lanes = o.lanes == 0 ? default_lanes(o.precision) : o.lanes;
  if (lanes != 8 && lanes != 16) throw Error("lanes must be 8 or 16 (got " + std::to_string(lanes) + ")");
  return lanes;
}

// Device-side copies of a real-valued host array, in the program's precision.
cl::Buffer real_buffer(Device::Impl& dev, Precision p, const std::vector<double>& v, cl_mem_flags flags = CL_MEM_READ_ONLY) {
  const std::vector<double> data = v.empty() ? std::vector<double>{0.0} : v;
  if (p == Precision::Fp64)
    return cl::Buffer(dev.context, flags | CL_MEM_COPY_HOST_PTR, data.size() * sizeof(double), const_cast<double*>(data.data()));
  std::vector<float> f(data.begin(), data.end());
  return cl::Buffer(dev.context, flags | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
}

size_t real_size(Precision p) { return p == Precision::Fp64 ? sizeof(double) : sizeof(float); }

// Reads n reals from a device buffer into doubles.
void read_reals(Device::Impl& dev, Precision p, const cl::Buffer& buffer, size_t n, double* out) {
  if (p == Precision::Fp64) {
    dev.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, n * sizeof(double), out);
    return;
  }
  std::vector<float> f(n);
  dev.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, n * sizeof(float), f.data());
  std::copy(f.begin(), f.end(), out);
}

// The parameter blocks and sheen tables of a set of materials.
struct Packed {
  std::vector<double> params;  // BRDF_PARAM_STRIDE per material
  std::vector<double> sheen;   // the E(mu) pieces of each distinct sheen roughness
};
Packed pack(BrdfModel model, const std::vector<Material>& materials) {
  Packed out;
  std::map<double, size_t> sheen_offsets;
  for (const Material& m : materials) {
    double offset = 0.0;
    if (has_sheen(model, m)) {
      auto it = sheen_offsets.find(m.sheen_roughness);
      if (it == sheen_offsets.end()) {
        it = sheen_offsets.emplace(m.sheen_roughness, out.sheen.size()).first;
        const auto& t = detail::sheen_albedo_pieces(m.sheen_roughness);
        out.sheen.insert(out.sheen.end(), t.begin(), t.end());
      }
      offset = static_cast<double>(it->second);
    }
    const Block b = pack_material(model, m, offset);
    out.params.insert(out.params.end(), b.begin(), b.end());
  }
  return out;
}

std::string fmt(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

const char* kConventions =
    "f is the BRDF without the cosine (radiance per irradiance, 1/sr), linear RGB; directions in tangent "
    "space, normal +z, tangent +x (Disney's alpha_x axis), bitangent +y; f = 0 where wi or wo is at or "
    "below the horizon; above it n.wi and n.wo are floored at 1e-7; roughness is perceptual, alpha = "
    "roughness^2 (docs/CONVENTIONS.md, BRDF evaluation)";

}  // namespace

std::string detail::pair_error(size_t i, const char* which) {
  return "direction pair " + std::to_string(i) + ": " + which + " is zero or not finite";
}

bool detail::unit_direction(const double* v, double* out) {
  const double m = std::max(std::fabs(v[0]), std::max(std::fabs(v[1]), std::fabs(v[2])));
  if (!(m > 0.0) || !std::isfinite(m) || !std::isfinite(v[0] + v[1] + v[2])) return false;
  const double x = v[0] / m, y = v[1] / m, z = v[2] / m;
  const double len = std::sqrt(x * x + y * y + z * z);
  out[0] = x / len;
  out[1] = y / len;
  out[2] = z / len;
  return true;
}

// ---- Names ----------------------------------------------------------------------------------------

BrdfModel brdf_model_from_name(const std::string& name) {
  std::string expected;
  for (const ModelName& m : kModels) {
    if (name == m.name) return m.model;
    expected += (expected.empty() ? "" : ", ") + std::string(m.name);
  }
  throw Error("unknown model '" + name + "' (expected " + expected + ")");
}

const char* brdf_model_name(BrdfModel model) { return model_entry(model).name; }

const std::vector<BrdfModel>& brdf_models() {
  static const std::vector<BrdfModel> models = [] {
    std::vector<BrdfModel> v;
    for (const ModelName& m : kModels) v.push_back(m.model);
    return v;
  }();
  return models;
}

TableLayout table_layout_from_name(const std::string& name) {
  for (int k = 0; k < 4; ++k)
    if (name == kLayoutNames[k]) return static_cast<TableLayout>(k);
  throw Error("unknown layout '" + name + "' (expected merl, grid, albedo, slice)");
}

const char* table_layout_name(TableLayout layout) { return kLayoutNames[static_cast<int>(layout)]; }

// ---- Lobes ----------------------------------------------------------------------------------------

Lobes lobes_used(BrdfModel model, const std::vector<Material>& materials) {
  Lobes l;
  for (const Material& m : materials) {
    switch (model) {
      case BrdfModel::Disney:
        l.diffuse |= m.metallic < 1.0;
        l.subsurface |= m.metallic < 1.0 && m.subsurface > 0.0;
        l.sheen |= m.metallic < 1.0 && m.sheen > 0.0;
        l.clearcoat |= m.clearcoat > 0.0;
        l.anisotropic |= m.anisotropic > 0.0;
        break;
      case BrdfModel::Gltf:
      case BrdfModel::GltfCorrelated: {
        l.diffuse |= m.metallic < 1.0;
        l.metal |= m.metallic > 0.0;
        const double q = (1.0 - m.ior) / (1.0 + m.ior), f0 = q * q;
        const Rgb& s = m.specular_color_factor;
        const bool grey = std::min(f0 * s.r, 1.0) == std::min(f0 * s.g, 1.0) && std::min(f0 * s.g, 1.0) == std::min(f0 * s.b, 1.0);
        l.specular_color |= m.metallic < 1.0 && (!grey || m.specular_factor != 1.0);
        l.sheen |= max3(m.sheen_color) > 0.0;
        l.clearcoat |= m.clearcoat > 0.0;
        break;
      }
      case BrdfModel::CookTorrance:
        l.beckmann |= m.distribution == MicrofacetDistribution::Beckmann;
        l.ggx |= m.distribution == MicrofacetDistribution::Ggx;
        break;
      default: break;
    }
  }
  return l;
}

Lobes all_lobes(BrdfModel model) {
  Lobes l;
  switch (model) {
    case BrdfModel::Disney:
      l.diffuse = l.subsurface = l.sheen = l.clearcoat = l.anisotropic = true;
      break;
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated:
      l.diffuse = l.metal = l.specular_color = l.sheen = l.clearcoat = true;
      break;
    case BrdfModel::CookTorrance: l.beckmann = l.ggx = true; break;
    default: break;
  }
  return l;
}

std::string lobes_name(BrdfModel, const Lobes& l) {
  std::string s;
  const std::pair<bool, const char*> flags[] = {{l.diffuse, "diffuse"},   {l.subsurface, "subsurface"},
                                                {l.sheen, "sheen"},       {l.clearcoat, "clearcoat"},
                                                {l.anisotropic, "anisotropic"}, {l.metal, "metal"},
                                                {l.specular_color, "specular-color"}, {l.beckmann, "beckmann"},
                                                {l.ggx, "ggx"}};
  for (const auto& [on, name] : flags)
    if (on) s += (s.empty() ? "" : ",") + std::string(name);
  return s.empty() ? "none" : s;
}

// ---- Evaluation -----------------------------------------------------------------------------------

constexpr size_t kPairPlanes = 9;  // wi, wo, h (kernels/brdf_eval.cl, brdf_pairs)

struct BrdfEvaluator::Impl {
  std::optional<Device> device;
  BrdfModel model;
  std::vector<Material> materials;
  EvalOptions options;
  int lanes;
  Lobes lobes;
  cl::Program program;
  cl::Buffer params, sheen;
  cl::Buffer dirs, out;
  size_t capacity = 0;  // pairs the dirs/out buffers hold
  std::vector<double> staging;
};

BrdfEvaluator::BrdfEvaluator(Device& device, BrdfModel model, std::vector<Material> materials,
                             const EvalOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.device = device;
  s.model = model;
  s.materials = std::move(materials);
  s.options = options;
  if (s.materials.empty()) throw Error("no materials to evaluate");
  for (size_t i = 0; i < s.materials.size(); ++i) validate_material(s.materials[i], "material " + std::to_string(i));
  s.lanes = resolve_lanes(options);
  s.lobes = options.specialize ? lobes_used(model, s.materials) : all_lobes(model);
  auto& dev = device.impl();
  s.program = detail::build_program(dev, program_spec(model, s.lobes, options, s.lanes));
  const Packed p = pack(model, s.materials);
  detail::cl_call("uploading materials", [&] {
    s.params = real_buffer(dev, options.precision, p.params);
    s.sheen = real_buffer(dev, options.precision, p.sheen);
  });
}

BrdfEvaluator::~BrdfEvaluator() = default;

const Lobes& BrdfEvaluator::lobes() const { return impl_->lobes; }
size_t BrdfEvaluator::material_count() const { return impl_->materials.size(); }
int BrdfEvaluator::lanes() const { return impl_->lanes; }

void BrdfEvaluator::eval(const double* pairs, size_t count, double* out, EvalTiming* timing) {
  const auto t0 = Clock::now();
  Impl& s = *impl_;
  if (count == 0) {
    if (timing) *timing = {};
    return;
  }
  auto& dev = s.device->impl();
  const size_t lanes = static_cast<size_t>(s.lanes);
  const size_t stride = (count + lanes - 1) / lanes * lanes;
  if (stride > static_cast<size_t>(INT32_MAX)) throw Error("too many direction pairs in one batch");
  const size_t n_mat = s.materials.size();
  const Precision p = s.options.precision;

  // Normalise (in double) into nine planes of `stride` values, zero-padded: wi, wo and their half
  // vector (kernels/brdf_eval.cl, brdf_pairs, says why h is formed here).
  s.staging.assign(kPairPlanes * stride, 0.0);
  for (size_t i = 0; i < count; ++i) {
    double wi[3], wo[3], h[3];
    if (!detail::unit_direction(pairs + 6 * i, wi)) throw Error(detail::pair_error(i, "wi"));
    if (!detail::unit_direction(pairs + 6 * i + 3, wo)) throw Error(detail::pair_error(i, "wo"));
    const double sum[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
    if (!detail::unit_direction(sum, h)) h[0] = h[1] = 0.0, h[2] = 1.0;  // wi = -wo: no half vector (and f = 0)
    for (size_t c = 0; c < 3; ++c) {
      s.staging[c * stride + i] = wi[c];
      s.staging[(3 + c) * stride + i] = wo[c];
      s.staging[(6 + c) * stride + i] = h[c];
    }
  }
  const std::string what = "kernel brdf_pairs on '" + dev.info.name + "'";
  const double device_seconds = detail::cl_call(what, [&] {
    if (stride > s.capacity) {
      s.dirs = cl::Buffer(dev.context, CL_MEM_READ_ONLY, kPairPlanes * stride * real_size(p));
      s.out = cl::Buffer(dev.context, CL_MEM_WRITE_ONLY, 3 * n_mat * stride * real_size(p));
      s.capacity = stride;
    }
    if (p == Precision::Fp64) {
      dev.queue.enqueueWriteBuffer(s.dirs, CL_FALSE, 0, kPairPlanes * stride * sizeof(double), s.staging.data());
    } else {
      // Components below FLT_MIN are flushed to zero here rather than left to the device's denormal
      // mode: in fp32 a cosine under 1.2e-38 is the horizon (docs/CONVENTIONS.md).
      std::vector<float> f(s.staging.size());
      for (size_t k = 0; k < f.size(); ++k) {
        const float v = static_cast<float>(s.staging[k]);
        f[k] = std::fabs(v) < std::numeric_limits<float>::min() ? 0.0f : v;
      }
      dev.queue.enqueueWriteBuffer(s.dirs, CL_TRUE, 0, f.size() * sizeof(float), f.data());
    }
    cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl::Buffer> kernel(s.program, "brdf_pairs");
    cl::Event e = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(stride / lanes, n_mat)), s.dirs,
                         static_cast<cl_int>(stride), s.params, s.sheen, s.out);
    e.wait();
    std::vector<double> planes(3 * n_mat * stride);
    read_reals(dev, p, s.out, planes.size(), planes.data());
    for (size_t m = 0; m < n_mat; ++m)
      for (size_t c = 0; c < 3; ++c) {
        const double* src = planes.data() + (m * 3 + c) * stride;
        for (size_t i = 0; i < count; ++i) out[(m * count + i) * 3 + c] = src[i];
      }
    return detail::event_seconds(e);
  });
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = seconds_since(t0);
  }
}

// ---- Tabulation -----------------------------------------------------------------------------------

namespace {

constexpr int kMaxRes = 8192;
constexpr long long kMaxCells = 1ll << 26;

// Albedo quadrature shape (kernels/brdf_eval.cl, brdf_albedo): panel A takes composite 8-point
// Gauss-Legendre panels of width <= kAlbedoPanelY in y = ln tan t, panel B kAlbedoNodesB nodes, the
// azimuth kAlbedoNodesPhi. Their accuracy is measured in tests/device and docs/BENCHMARKS.md.
constexpr double kAlbedoPanelY = 0.5;
constexpr double kAlbedoStart = 1e-4;
constexpr double kAlbedoStartMax = 1e-5;
constexpr int kAlbedoNodesB = 96;
constexpr int kAlbedoNodesPhi = 64;

}  // namespace

void detail::check_tabulate_spec(const TabulateSpec& s) {
  if (s.materials.empty()) throw Error("no materials to tabulate");
  if (s.layout != TableLayout::Albedo && s.materials.size() != 1)
    throw Error(std::string("layout ") + table_layout_name(s.layout) + " tabulates one material (got " +
                std::to_string(s.materials.size()) + ")");
  for (const NamedMaterial& m : s.materials) validate_material(m.params, "material '" + m.name + "'");
  if (!(s.slice_phi_d >= 0.0 && s.slice_phi_d <= kPi))
    throw Error("slice phi_d must be in [0, pi] (got " + fmt(s.slice_phi_d) + ")");
}

namespace {

std::vector<Material> params_of(const TabulateSpec& s) {
  std::vector<Material> v;
  for (const NamedMaterial& m : s.materials) v.push_back(m.params);
  return v;
}

}  // namespace

void detail::tabulate_metadata(Metadata& meta, const TabulateSpec& s, const std::vector<int>& res, const std::string& device,
                 const std::string& precision, const std::string& lobes) {
  auto set = [&](const std::string& k, const std::string& v) {
    for (auto& kv : meta)
      if (kv.first == k) {
        kv.second = v;
        return;
      }
    meta.emplace_back(k, v);
  };
  set("generator", std::string("brdfbake ") + kVersion);
  set("model", brdf_model_name(s.model));
  std::string materials = "[";
  for (size_t i = 0; i < s.materials.size(); ++i) materials += (i ? "," : "") + material_to_json(s.materials[i]);
  set("materials", materials + "]");
  set("layout", table_layout_name(s.layout));
  std::string r;
  for (int v : res) r += (r.empty() ? "" : "x") + std::to_string(v);
  set("resolution", r);
  set("precision", precision);
  set("device", device);
  set("lobes", lobes);
  set("conventions", kConventions);
}

namespace {

std::string device_name(Device::Impl& dev) {
  return dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")";
}

std::string precision_label(const EvalOptions& o) {
  return std::string(precision_name(o.precision)) + (o.fast_math ? " -cl-fast-relaxed-math" : "");
}

}  // namespace

Table detail::make_tabulate_table(const TabulateSpec& s, const std::vector<int>& res) {
  Table t;
  t.channels = {"r", "g", "b"};
  switch (s.layout) {
    case TableLayout::Grid: {
      const int ni = res[0], no = res[1], np = res[2];
      t.width = no;
      t.height = ni * np;
      t.x_name = "theta_o";
      t.y_name = "theta_i";
      for (int j = 0; j < no; ++j) t.x.push_back((j + 0.5) / no * kHalfPi);
      for (int k = 0; k < np; ++k)
        for (int i = 0; i < ni; ++i) t.y.push_back((i + 0.5) / ni * kHalfPi);
      t.set_meta("axes",
                 "column j: theta_o = (j + 0.5) / " + std::to_string(no) + " pi/2; row k * " + std::to_string(ni) +
                     " + i: theta_i = (i + 0.5) / " + std::to_string(ni) + " pi/2, phi_d = (k + 0.5) / " +
                     std::to_string(np) + " pi; wi = (sin theta_i, 0, cos theta_i), wo = (sin theta_o cos phi_d, "
                     "sin theta_o sin phi_d, cos theta_o); angles in radians");
      break;
    }
    case TableLayout::Albedo: {
      const int n = res[0];
      t.width = n;
      t.height = static_cast<int>(s.materials.size());
      t.x_name = "theta_o";
      t.y_name = "material";
      for (int i = 0; i < n; ++i) t.x.push_back((i + 0.5) / n * kHalfPi);
      std::string names;
      for (size_t m = 0; m < s.materials.size(); ++m) {
        t.y.push_back(static_cast<double>(m));
        names += (m ? "," : "") + s.materials[m].name;
      }
      t.set_meta("axes", "column i: theta_o = (i + 0.5) / " + std::to_string(n) +
                             " pi/2 (radians), wo = (sin theta_o, 0, cos theta_o); row m: material m");
      t.set_meta("material_names", names);
      t.set_meta("definition", "directional albedo a(wo) = integral over the hemisphere of f(wi, wo) n.wi dwi");
      break;
    }
    case TableLayout::Slice: {
      const int w = res[0], h = res[1];
      t.width = w;
      t.height = h;
      t.x_name = "theta_h";
      t.y_name = "theta_d";
      for (int i = 0; i < w; ++i) t.x.push_back((i + 0.5) / w * kHalfPi);
      for (int j = 0; j < h; ++j) t.y.push_back((j + 0.5) / h * kHalfPi);
      t.set_meta("axes", "column i: theta_h = (i + 0.5) / " + std::to_string(w) + " pi/2, row j: theta_d = (j + 0.5) / " +
                             std::to_string(h) + " pi/2, phi_d = " + fmt(s.slice_phi_d) +
                             ", phi_h = 0 (Rusinkiewicz half/difference angles, radians); wi = R_y(theta_h) d, "
                             "wo = 2 (wi.h) h - wi; 0 where a direction is below the horizon");
      t.set_meta("phi_d", fmt(s.slice_phi_d));
      break;
    }
    case TableLayout::Merl: break;
  }
  t.data.assign(static_cast<size_t>(t.width) * static_cast<size_t>(t.height) * 3, 0.0f);
  return t;
}

void detail::merl_metadata(Metadata& meta) {
  meta.emplace_back("merl_layout",
                    "bin (i, j, k) of theta_h, theta_d, phi_d holds f at theta_h = ((i + 0.5)/90)^2 pi/2, theta_d = "
                    "(j + 0.5)/90 pi/2, phi_d = (k + 0.5)/180 pi, phi_h = 0, stored as f / scale with scale = "
                    "1/1500, 1.15/1500, 1.66/1500 (red, green, blue); -1 where a direction is below the horizon");
}

namespace {

// The albedo quadrature nodes (layout in kernels/brdf_eval.cl, brdf_albedo).
std::vector<double> albedo_nodes(int n_a, int n_b, int n_p) {
  std::vector<double> q;
  const auto& g8 = math::gauss_legendre(8);
  const int panels = n_a / 8;
  std::vector<double> xa, wa;
  for (int p = 0; p < panels; ++p)
    for (size_t k = 0; k < 8; ++k) {
      xa.push_back((p + 0.5 * (1.0 + g8.nodes[k])) / panels);
      wa.push_back(0.5 * g8.weights[k] / panels);
    }
  q.insert(q.end(), xa.begin(), xa.end());
  q.insert(q.end(), wa.begin(), wa.end());
  const auto& gb = math::gauss_legendre(n_b);
  for (int k = 0; k < n_b; ++k) q.push_back(0.5 * (1.0 - std::cos(kPi * 0.5 * (1.0 + gb.nodes[size_t(k)]))));
  for (int k = 0; k < n_b; ++k) {
    const double x = 0.5 * (1.0 + gb.nodes[size_t(k)]);
    q.push_back(0.5 * kPi * std::sin(kPi * x) * 0.5 * gb.weights[size_t(k)]);
  }
  for (int j = 0; j < n_p; ++j) q.push_back(std::cos((j + 0.5) * kPi / n_p));
  for (int j = 0; j < n_p; ++j) q.push_back(std::sin((j + 0.5) * kPi / n_p));
  const auto& gp = math::gauss_legendre(n_p);
  for (int j = 0; j < n_p; ++j) q.push_back(0.5 * (1.0 + gp.nodes[size_t(j)]));
  for (int j = 0; j < n_p; ++j) q.push_back(0.5 * gp.weights[size_t(j)]);
  return q;
}

}  // namespace

std::vector<int> tabulate_resolution(const TabulateSpec& s) {
  std::vector<int> res = s.res;
  size_t want = 0;
  std::vector<int> defaults;
  switch (s.layout) {
    case TableLayout::Merl:
      if (!res.empty() && res != std::vector<int>{kMerlThetaH, kMerlThetaD, kMerlPhiD})
        throw Error("the merl layout has a fixed resolution (90 x 90 x 180); leave --res out");
      return {kMerlThetaH, kMerlThetaD, kMerlPhiD};
    case TableLayout::Grid: want = 3; defaults = {32, 32, 32}; break;
    case TableLayout::Albedo: want = 1; defaults = {90}; break;
    case TableLayout::Slice: want = 2; defaults = {256, 256}; break;
  }
  if (res.empty()) res = defaults;
  if (res.size() == 1) res.assign(want, res[0]);
  if (res.size() != want)
    throw Error(std::string("layout ") + table_layout_name(s.layout) + " takes " + std::to_string(want) +
                " resolution values or one for all (got " + std::to_string(res.size()) + ")");
  long long cells = 1;
  for (int v : res) {
    if (v < 1 || v > kMaxRes)
      throw Error("resolution values must be in [1, " + std::to_string(kMaxRes) + "] (got " + std::to_string(v) + ")");
    cells *= v;
  }
  if (cells > kMaxCells) throw Error("the table has too many cells (at most " + std::to_string(kMaxCells) + ")");
  return res;
}

MerlTable tabulate_merl(Device& device, const TabulateSpec& s, TabulateTiming* timing) {
  const auto t0 = Clock::now();
  if (s.layout != TableLayout::Merl) throw Error("tabulate_merl needs the merl layout");
  detail::check_tabulate_spec(s);
  const std::vector<int> res = tabulate_resolution(s);
  auto& dev = device.impl();
  const int lanes = resolve_lanes(s.options);
  const std::vector<Material> mats = params_of(s);
  const Lobes lobes = s.options.specialize ? lobes_used(s.model, mats) : all_lobes(s.model);
  cl::Program program = detail::build_program(dev, program_spec(s.model, lobes, s.options, lanes));
  const Packed p = pack(s.model, mats);
  MerlTable t;
  t.values.resize(3 * kMerlBins);
  const Precision prec = s.options.precision;
  const double device_seconds = detail::cl_call("kernel brdf_merl on '" + dev.info.name + "'", [&] {
    cl::Buffer params = real_buffer(dev, prec, p.params), sheen = real_buffer(dev, prec, p.sheen);
    cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, 3 * kMerlBins * real_size(prec));
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl::Buffer> kernel(program, "brdf_merl");
    cl::Event e = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(kMerlBins / static_cast<size_t>(lanes))), params,
                         sheen, 0, out);
    e.wait();
    read_reals(dev, prec, out, t.values.size(), t.values.data());
    return detail::event_seconds(e);
  });
  detail::tabulate_metadata(t.metadata, s, res, device_name(dev), precision_label(s.options), lobes_name(s.model, lobes));
  detail::merl_metadata(t.metadata);
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = seconds_since(t0);
  }
  return t;
}

Table tabulate(Device& device, const TabulateSpec& s, TabulateTiming* timing) {
  const auto t0 = Clock::now();
  if (s.layout == TableLayout::Merl) throw Error("the merl layout is written by tabulate_merl");
  detail::check_tabulate_spec(s);
  const std::vector<int> res = tabulate_resolution(s);
  auto& dev = device.impl();
  const int lanes = resolve_lanes(s.options);
  const std::vector<Material> mats = params_of(s);
  const Lobes lobes = s.options.specialize ? lobes_used(s.model, mats) : all_lobes(s.model);
  cl::Program program = detail::build_program(dev, program_spec(s.model, lobes, s.options, lanes));
  const Packed packed = pack(s.model, mats);
  Table t = detail::make_tabulate_table(s, res);
  const Precision prec = s.options.precision;
  const size_t l = static_cast<size_t>(lanes);
  const std::string what = std::string("kernel brdf_") + table_layout_name(s.layout) + " on '" + dev.info.name + "'";
  const double device_seconds = detail::cl_call(what, [&] {
    cl::Buffer params = real_buffer(dev, prec, packed.params), sheen = real_buffer(dev, prec, packed.sheen);
    cl::Event e;
    std::vector<double> planes;
    size_t plane = 0;
    if (s.layout == TableLayout::Albedo) {
      const int n = res[0];
      double y_lowest = 0.0;
      std::vector<double> y_min;
      for (const Material& m : mats) {
        // the polar angles below 1e-4 of the narrowest lobe (and below 1e-5 rad) hold less than
        // 1e-8 of its albedo: the integrand grows like t^2 there (dh = sin t dt)
        y_min.push_back(std::log(std::min(kAlbedoStart * narrowest_lobe(s.model, m), kAlbedoStartMax)));
        y_lowest = std::min(y_lowest, y_min.back());
      }
      const int n_a = 8 * std::max(1, static_cast<int>(std::ceil(-y_lowest / kAlbedoPanelY)));
      const int n_a_padded = (n_a + lanes - 1) / lanes * lanes;
      std::vector<double> q = albedo_nodes(n_a, kAlbedoNodesB, kAlbedoNodesPhi);
      // pad panel A with zero-weight nodes to a multiple of the lane width
      std::vector<double> qa(q.begin(), q.begin() + n_a), wa(q.begin() + n_a, q.begin() + 2 * n_a);
      qa.resize(static_cast<size_t>(n_a_padded), 0.5);
      wa.resize(static_cast<size_t>(n_a_padded), 0.0);
      std::vector<double> qq = qa;
      qq.insert(qq.end(), wa.begin(), wa.end());
      qq.insert(qq.end(), q.begin() + 2 * n_a, q.end());
      cl::Buffer qb = real_buffer(dev, prec, qq), yb = real_buffer(dev, prec, y_min);
      plane = static_cast<size_t>(n);
      cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, 3 * mats.size() * plane * real_size(prec));
      cl::KernelFunctor<cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl::Buffer, cl_int, cl_int, cl_int, cl::Buffer>
          kernel(program, "brdf_albedo");
      e = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(static_cast<size_t>(n), mats.size())), params, sheen, yb, n, qb,
                 n_a_padded, kAlbedoNodesB, kAlbedoNodesPhi, out);
      e.wait();
      planes.resize(3 * mats.size() * plane);
      read_reals(dev, prec, out, planes.size(), planes.data());
      for (size_t m = 0; m < mats.size(); ++m)
        for (int i = 0; i < n; ++i)
          for (int c = 0; c < 3; ++c)
            t.at(i, static_cast<int>(m), c) = static_cast<float>(planes[(m * 3 + size_t(c)) * plane + size_t(i)]);
    } else {
      const size_t cells = static_cast<size_t>(t.width) * static_cast<size_t>(t.height);
      plane = (cells + l - 1) / l * l;
      cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, 3 * plane * real_size(prec));
      if (s.layout == TableLayout::Grid) {
        cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl_int, cl_int, cl_int, cl::Buffer> kernel(program, "brdf_grid");
        e = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(plane / l)), params, sheen, 0, res[0], res[1], res[2], out);
      } else if (prec == Precision::Fp64) {
        cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl_int, cl_int, cl_double, cl::Buffer> kernel(program, "brdf_slice");
        e = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(plane / l)), params, sheen, 0, res[0], res[1], s.slice_phi_d, out);
      } else {
        cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl_int, cl_int, cl_float, cl::Buffer> kernel(program, "brdf_slice");
        e = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(plane / l)), params, sheen, 0, res[0], res[1],
                   static_cast<float>(s.slice_phi_d), out);
      }
      e.wait();
      planes.resize(3 * plane);
      read_reals(dev, prec, out, planes.size(), planes.data());
      for (size_t b = 0; b < cells; ++b)
        for (size_t c = 0; c < 3; ++c) t.data[b * 3 + c] = static_cast<float>(planes[c * plane + b]);
    }
    return detail::event_seconds(e);
  });
  detail::tabulate_metadata(t.metadata, s, res, device_name(dev), precision_label(s.options), lobes_name(s.model, lobes));
  if (s.layout == TableLayout::Albedo)
    t.set_meta("method", "deterministic quadrature over the half vector, split at the horizon (kernels/brdf_eval.cl)");
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = seconds_since(t0);
  }
  return t;
}

}  // namespace brdfbake
