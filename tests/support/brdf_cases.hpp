// Materials and direction pairs shared by the BRDF tests: random valid inputs and the corners the
// bulk-BRDF issue names (horizon, wi = wo, wi = -wo, grazing, roughness/anisotropy/metallic and every
// lobe weight at 0 and 1). The materials are generated for either parameter type, the public API's
// (brdfbake::Material, BrdfModel: tests/device) or the reference's own (reference::BrdfMaterial,
// reference::BrdfModel: tests/reference): both have the same fields and enumerators.
#pragma once

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/types.hpp"

namespace brdfbake::test {

template <class BrdfModel>
const std::vector<BrdfModel>& all_models() {
  static const std::vector<BrdfModel> models = {
      BrdfModel::Disney, BrdfModel::Gltf,       BrdfModel::GltfCorrelated, BrdfModel::Lambert,
      BrdfModel::Phong,  BrdfModel::BlinnPhong, BrdfModel::CookTorrance,   BrdfModel::BlinnPhongFromPbr};
  return models;
}

// A unit direction rounded to float, as a double triple: what the device sees.
inline Vec3 float_unit(double x, double y, double z) {
  const double len = std::sqrt(x * x + y * y + z * z);
  return {double(float(x / len)), double(float(y / len)), double(float(z / len))};
}

inline Vec3 from_angles(double theta, double phi) {
  return float_unit(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// Random materials with every parameter in its valid range; a quarter of the draws of each weight
// land exactly on 0 or 1.
template <class BrdfMaterial, class BrdfModel>
BrdfMaterial random_material(BrdfModel model, std::mt19937& rng) {
  using Distribution = decltype(BrdfMaterial{}.distribution);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto unit = [&] {
    const double k = u(rng);
    return k < 0.125 ? 0.0 : k < 0.25 ? 1.0 : u(rng);
  };
  auto colour = [&] { return Rgb{u(rng), u(rng), u(rng)}; };
  BrdfMaterial m;
  m.base_color = colour();
  m.metallic = unit();
  m.roughness = unit();
  switch (model) {
    case BrdfModel::Disney:
      m.subsurface = unit();
      m.specular = unit();
      m.specular_tint = unit();
      m.anisotropic = unit();
      m.sheen = unit();
      m.sheen_tint = unit();
      m.clearcoat = unit();
      m.clearcoat_gloss = unit();
      break;
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated:
      m.clearcoat = u(rng) < 0.5 ? 0.0 : unit();
      m.clearcoat_roughness = unit();
      m.ior = u(rng) < 0.2 ? 0.0 : 1.0 + 1.5 * u(rng);
      m.specular_factor = unit();
      m.specular_color_factor = Rgb{2.0 * u(rng), 2.0 * u(rng), 2.0 * u(rng)};
      // sheen tables cost ~1 s per distinct roughness: a few fixed values
      if (u(rng) < 0.5) {
        m.sheen_color = colour();
        const double rs[] = {0.0, 0.3, 1.0};
        m.sheen_roughness = rs[std::uniform_int_distribution<int>(0, 2)(rng)];
      }
      break;
    case BrdfModel::Phong:
    case BrdfModel::BlinnPhong:
      m.normalized = u(rng) < 0.7;
      if (u(rng) < 0.5) m.shininess = std::pow(10.0, 4.0 * u(rng));
      if (u(rng) < 0.5) m.diffuse_color = colour();
      if (u(rng) < 0.5) m.specular_color = colour();
      break;
    case BrdfModel::CookTorrance:
      m.distribution = u(rng) < 0.5 ? Distribution::Beckmann : Distribution::Ggx;
      if (u(rng) < 0.5) m.specular_color = Rgb{unit(), u(rng), u(rng)};
      break;
    default:
      break;
  }
  return m;
}

// The corner materials of a model: roughness, anisotropy, metallic and every lobe weight at 0 and 1.
template <class BrdfMaterial, class BrdfModel>
std::vector<std::pair<std::string, BrdfMaterial>> corner_materials(BrdfModel model) {
  using Distribution = decltype(BrdfMaterial{}.distribution);
  std::vector<std::pair<std::string, BrdfMaterial>> out;
  BrdfMaterial base;
  base.base_color = {0.9, 0.5, 0.2};
  for (double r : {0.0, 1.0})
    for (double metal : {0.0, 1.0}) {
      BrdfMaterial m = base;
      m.roughness = r;
      m.metallic = metal;
      out.push_back({"roughness " + std::to_string(r) + " metallic " + std::to_string(metal), m});
    }
  auto add = [&](const std::string& name, auto set) {
    for (double w : {0.0, 1.0})
      for (double r : {0.0, 0.5}) {
        BrdfMaterial m = base;
        m.roughness = r;
        set(m, w);
        out.push_back({name + " " + std::to_string(w) + " roughness " + std::to_string(r), m});
      }
  };
  switch (model) {
    case BrdfModel::Disney:
      add("subsurface", [](BrdfMaterial& m, double w) { m.subsurface = w; });
      add("specular", [](BrdfMaterial& m, double w) { m.specular = w; });
      add("specularTint", [](BrdfMaterial& m, double w) { m.specular_tint = w; });
      add("anisotropic", [](BrdfMaterial& m, double w) { m.anisotropic = w; });
      add("sheen", [](BrdfMaterial& m, double w) { m.sheen = w; });
      add("sheenTint", [](BrdfMaterial& m, double w) { m.sheen_tint = w; });
      add("clearcoat", [](BrdfMaterial& m, double w) { m.clearcoat = w; });
      add("clearcoatGloss", [](BrdfMaterial& m, double w) {
        m.clearcoat = 1.0;
        m.clearcoat_gloss = w;
      });
      break;
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated:
      add("clearcoat", [](BrdfMaterial& m, double w) { m.clearcoat = w; });
      add("clearcoatRoughness", [](BrdfMaterial& m, double w) {
        m.clearcoat = 1.0;
        m.clearcoat_roughness = w;
      });
      add("sheenColor", [](BrdfMaterial& m, double w) { m.sheen_color = {w, w, w}; });
      add("sheenRoughness", [](BrdfMaterial& m, double w) {
        m.sheen_color = {1.0, 0.5, 0.25};
        m.sheen_roughness = w;
      });
      add("specularFactor", [](BrdfMaterial& m, double w) { m.specular_factor = w; });
      add("ior", [](BrdfMaterial& m, double w) { m.ior = w == 0.0 ? 0.0 : 1.0; });
      break;
    case BrdfModel::Phong:
    case BrdfModel::BlinnPhong:
      add("normalized", [](BrdfMaterial& m, double w) { m.normalized = w > 0.5; });
      add("shininess", [](BrdfMaterial& m, double w) { m.shininess = w == 0.0 ? 0.0 : math::kMaxShininess; });
      break;
    case BrdfModel::CookTorrance:
      add("beckmann",
          [](BrdfMaterial& m, double w) { m.distribution = w > 0.5 ? Distribution::Beckmann : Distribution::Ggx; });
      add("specularColor", [](BrdfMaterial& m, double w) { m.specular_color = Rgb{w, w, w}; });
      break;
    default:
      break;
  }
  return out;
}

// Random pairs: uniform on the sphere, so a quarter have both directions above the horizon and the
// rest test the zero below it; plus as many pairs that are both in the upper hemisphere.
inline std::vector<std::pair<Vec3, Vec3>> random_pairs(std::mt19937& rng, int n) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::pair<Vec3, Vec3>> out;
  for (int k = 0; k < n; ++k) {
    Vec3 a = float_unit(g(rng), g(rng), g(rng)), b = float_unit(g(rng), g(rng), g(rng));
    if (k % 2 == 1) {
      a.z = std::fabs(a.z);
      b.z = std::fabs(b.z);
    }
    out.push_back({a, b});
  }
  return out;
}

// The corner pairs: normal incidence, wi = wo, wi = -wo (the half vector undefined), mirror pairs,
// grazing on both sides of the horizon, exactly on it, and tiny or huge (non-unit) vectors.
inline std::vector<std::pair<Vec3, Vec3>> corner_pairs() {
  std::vector<std::pair<Vec3, Vec3>> out;
  const double pi = 3.14159265358979323846;
  const Vec3 n{0.0, 0.0, 1.0};
  out.push_back({n, n});
  for (double t : {0.3, 1.0, 1.5, pi / 2 - 1e-3, pi / 2 - 1e-6}) {
    const Vec3 a = from_angles(t, 0.4), b = from_angles(t, 0.4 + pi);
    out.push_back({a, a});                   // wi = wo
    out.push_back({a, b});                   // mirror pair: h = n exactly
    out.push_back({a, {-a.x, -a.y, -a.z}});  // wi = -wo
    out.push_back({a, {-a.x, -a.y, a.z}});   // mirror through the normal
    out.push_back({from_angles(0.2, 1.0), a});
  }
  // grazing on both sides of the horizon, and on it
  for (double z : {1e-7, 1e-20, 1e-38, 0.0, -1e-38, -1e-7}) {
    const Vec3 g{std::sqrt(1.0 - z * z), 0.0, z};
    out.push_back({g, n});
    out.push_back({n, g});
    out.push_back({g, g});
    out.push_back({g, {-g.x, 0.0, g.z}});  // both grazing, opposite: h nearly vertical and tiny
    out.push_back({g, {0.0, g.x, g.z}});
  }
  // not unit: tiny and huge vectors of the same directions
  out.push_back({{1e-30, 0.0, 1e-30}, {0.0, 2e-30, 1e-30}});
  out.push_back({{3e30, 1e30, 2e30}, {-1e30, 0.0, 5e30}});
  return out;
}

}  // namespace brdfbake::test
