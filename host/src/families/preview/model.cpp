// The preview's scene: materials, layout, camera and pixels (model.hpp).
#include "families/preview/model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "brdfbake/brdf.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "io/image_file.hpp"
#include "io/srgb.hpp"

namespace brdfbake {

Rgb preview_dielectric_f0(const PreviewMaterial& m) {
  // KHR_materials_ior: ((ior - 1) / (ior + 1))^2, 0.04 at the default 1.5 (written as the literal so
  // that a material without the extensions keeps glTF 2.0's value to the last bit); ior 0 gives 1.
  // KHR_materials_specular: times specularColorFactor, clamped to 1.
  const double r = (m.ior - 1.0) / (m.ior + 1.0);
  const double f = m.ior == 1.5 ? 0.04 : r * r;
  const Rgb& c = m.specular_color;
  return {std::min(f * c.r, 1.0), std::min(f * c.g, 1.0), std::min(f * c.b, 1.0)};
}

Rgb preview_f0(const PreviewMaterial& m) {
  // glTF 2.0, Appendix B: F0 = mix(dielectric F0, baseColor, metallic); KHR_materials_specular's
  // fresnel_mix scales the dielectric's Fresnel by specularFactor
  const Rgb d = preview_dielectric_f0(m);
  auto mix = [&](double f, double c) { return m.specular * f * (1.0 - m.metallic) + c * m.metallic; };
  return {mix(d.r, m.base_color.r), mix(d.g, m.base_color.g), mix(d.b, m.base_color.b)};
}

double preview_f90(const PreviewMaterial& m) {
  // mix(specular, 1, metallic), written so that specular 1 gives exactly 1
  return 1.0 - (1.0 - m.specular) * (1.0 - m.metallic);
}

double preview_coat_fresnel(double n_dot_v) {
  const double x = 1.0 - std::clamp(n_dot_v, 0.0, 1.0), x2 = x * x;
  return 0.04 + 0.96 * x2 * x2 * x;
}

bool preview_has_sheen(const PreviewMaterial& m) {
  return m.sheen_color.r > 0.0 || m.sheen_color.g > 0.0 || m.sheen_color.b > 0.0;
}

bool preview_has_iridescence(const PreviewMaterial& m) { return m.iridescence > 0.0; }

bool preview_has_specular_extension(const PreviewMaterial& m) {
  return m.ior != 1.5 || m.specular != 1.0 || m.specular_color.r != 1.0 || m.specular_color.g != 1.0 ||
         m.specular_color.b != 1.0;
}

Rgb preview_diffuse_color(const PreviewMaterial& m) {
  const double k = 1.0 - m.metallic;
  return {m.base_color.r * k, m.base_color.g * k, m.base_color.b * k};
}

std::vector<PreviewMaterial> preview_default_materials() {
  // Linear base colours: dielectrics white 0.8, grey 0.18 (middle grey), dark 0.03; metals by their
  // F0 at normal incidence (linear sRGB primaries; the values of the glTF sample models' gold, and
  // of Hoffman's tables for copper and silver).
  struct Base {
    const char* name;
    Rgb colour;
    double metallic;
  };
  const Base bases[] = {{"white", {0.8, 0.8, 0.8}, 0.0},        {"grey", {0.18, 0.18, 0.18}, 0.0},
                        {"dark", {0.03, 0.03, 0.03}, 0.0},      {"gold", {1.0, 0.766, 0.336}, 1.0},
                        {"copper", {0.955, 0.638, 0.538}, 1.0}, {"silver", {0.972, 0.960, 0.915}, 1.0}};
  const double roughness[kPreviewDefaultColumns] = {0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  std::vector<PreviewMaterial> out;
  for (const Base& b : bases)
    for (double r : roughness) {
      PreviewMaterial m;
      char name[64];
      std::snprintf(name, sizeof name, "%s r%.2g", b.name, r);
      m.name = name;
      m.base_color = b.colour;
      m.metallic = b.metallic;
      m.roughness = r;
      out.push_back(m);
    }
  return out;
}

PreviewBackground preview_background_from_name(const std::string& name) {
  return detail::enum_from_name(detail::preview::kBackgroundNames, name, "background");
}

const char* preview_background_name(PreviewBackground b) {
  return detail::enum_name(detail::preview::kBackgroundNames, b);
}

namespace detail::preview {

namespace {

std::string fmt_nm(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

// What of a material the preview does not render (it renders the metallic-roughness core).
std::vector<std::string> unrendered(const NamedMaterial& nm) {
  std::vector<std::string> notes = nm.notes;
  const Material& p = nm.params;
  if (nm.model && *nm.model != BrdfModel::Gltf && *nm.model != BrdfModel::GltfCorrelated)
    notes.push_back(std::string("model ") + brdf_model_name(*nm.model) +
                    ": rendered as glTF metallic-roughness (baseColor, metallic, roughness)");
  if ((p.sheen_color.r > 0 || p.sheen_color.g > 0 || p.sheen_color.b > 0) && nm.model && *nm.model == BrdfModel::Disney)
    notes.push_back("sheen: Disney's not rendered (the preview renders glTF's KHR_materials_sheen)");
  if (p.clearcoat > 0 && nm.model && *nm.model == BrdfModel::Disney)
    notes.push_back("clearcoat: Disney's not rendered (the preview renders glTF's KHR_materials_clearcoat)");
  // KHR_materials_iridescence: the preview renders it (its notes say how, per target: render.cpp);
  // eval's note that the gltf BRDF ignores it does not apply here
  const std::string eval_note = "KHR_materials_iridescence ignored (not part of the gltf BRDF here)";
  notes.erase(std::remove(notes.begin(), notes.end(), eval_note), notes.end());
  for (const std::string& n : nm.notes)
    if (n.rfind("KHR_materials_iridescence.iridescenceThicknessTexture", 0) == 0)
      notes.push_back(
          "KHR_materials_iridescence: the thickness texture is not read; the film is "
          "iridescenceThicknessMaximum (" +
          fmt_nm(p.iridescence_thickness) + " nm) thick everywhere, in both renders");
  return notes;
}

using io::linear_to_srgb;
using io::srgb_to_linear;

// The mean of an image's first three channels (one channel: repeated), as glTF reads the texture:
// `srgb` (baseColorTexture) decoded to linear, else (metallicRoughnessTexture) the stored values.
// io::read_image decodes what the file says is sRGB (an 8-bit PNG without a tag is sRGB); where it
// did not (transfer_note empty) the sRGB decoding is done here, and where it did but the texture is
// data, the stored values come back through the inverse. Every texel counts the same: a sphere has
// no texture coordinates of the mesh.
std::array<double, 3> texture_mean(const std::string& file, bool srgb) {
  io::ImageLimits limits;
  limits.max_bytes = default_memory_budget() / 4;
  const io::FloatImage img = io::read_image(file, limits);
  const bool decoded = !img.transfer_note.empty();
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  const size_t n = size_t(img.width) * size_t(img.height), ch = size_t(std::max(1, img.channels));
  for (size_t i = 0; i < n; ++i)
    for (size_t c = 0; c < 3; ++c) {
      double v = std::clamp(double(img.pixels[i * ch + std::min(c, ch - 1)]), 0.0, 1.0);
      if (srgb && !decoded) v = srgb_to_linear(v);
      if (!srgb && decoded) v = linear_to_srgb(v);
      sum[c] += v;
    }
  for (double& v : sum) v /= double(std::max<size_t>(1, n));
  return sum;
}

// A glTF material's baseColorTexture and metallicRoughnessTexture, read as their means times the
// factors when their images are files beside the scene (issue 34: SheenChair's wood, whose
// metalness is textured under metallicFactor 1, rendered as metal); the note on the sphere says so.
void apply_texture_means(const NamedMaterial& nm, PreviewMaterial& m) {
  const auto replace_note = [&m](const std::string& texture, const std::string& text) {
    const std::string ignored = "pbrMetallicRoughness." + texture + " ignored (textures are not read)";
    std::replace(m.notes.begin(), m.notes.end(), ignored, text);
  };
  const auto mean_of = [&](const std::string& file, const std::string& texture,
                           bool srgb) -> std::optional<std::array<double, 3>> {
    if (file.empty()) return std::nullopt;
    try {
      return texture_mean(file, srgb);
    } catch (const Error& e) {
      replace_note(texture, "pbrMetallicRoughness." + texture + " not read (" + std::string(e.what()).substr(0, 120) +
                                "): the factor alone");
      return std::nullopt;
    }
  };
  const auto f3 = [](double v) { return fmt_nm(std::round(v * 1000.0) / 1000.0); };
  if (const auto mean = mean_of(nm.base_color_image, "baseColorTexture", true)) {
    m.base_color = Rgb{m.base_color.r * (*mean)[0], m.base_color.g * (*mean)[1], m.base_color.b * (*mean)[2]};
    replace_note("baseColorTexture", "pbrMetallicRoughness.baseColorTexture: approximated by its mean (linear " +
                                         f3((*mean)[0]) + ", " + f3((*mean)[1]) + ", " + f3((*mean)[2]) +
                                         ") times baseColorFactor, one colour for the sphere");
  }
  if (const auto mean = mean_of(nm.metallic_roughness_image, "metallicRoughnessTexture", false)) {
    m.roughness *= (*mean)[1];  // glTF: roughness in G, metalness in B
    m.metallic *= (*mean)[2];
    replace_note("metallicRoughnessTexture",
                 "pbrMetallicRoughness.metallicRoughnessTexture: approximated by its mean (roughness " +
                     f3((*mean)[1]) + ", metallic " + f3((*mean)[2]) + ") times the factors");
  }
}

Vec3 rotate_y(const Vec3& a, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {a.x * c + a.z * s, a.y, -a.x * s + a.z * c};
}

Vec3 normalized(const Vec3& a) {
  const double l = std::sqrt(math::dot(a, a));
  return {a.x / l, a.y / l, a.z / l};
}

}  // namespace

PreviewSpec resolve_spec(const PreviewSpec& in) {
  PreviewSpec s = in;
  if (s.width < 16 || s.width > kPreviewMaxSize || s.height < 16 || s.height > kPreviewMaxSize)
    throw Error("width and height must be in 16.." + std::to_string(kPreviewMaxSize));
  if (s.materials.empty()) {
    if (s.materials_file.empty()) {
      s.materials = preview_default_materials();
      if (s.columns == 0) s.columns = kPreviewDefaultColumns;
    } else {
      for (const NamedMaterial& nm : read_materials(s.materials_file)) {
        PreviewMaterial m;
        m.name = nm.name;
        m.base_color = nm.params.base_color;
        m.metallic = nm.params.metallic;
        m.roughness = nm.params.roughness;
        m.ior = nm.params.ior;
        m.specular = nm.params.specular_factor;
        m.specular_color = nm.params.specular_color_factor;
        if (!nm.model || *nm.model != BrdfModel::Disney) {
          m.clearcoat = nm.params.clearcoat;
          m.clearcoat_roughness = nm.params.clearcoat_roughness;
          m.sheen_color = nm.params.sheen_color;
          m.sheen_roughness = nm.params.sheen_roughness;
          m.iridescence = nm.params.iridescence;
          m.iridescence_ior = nm.params.iridescence_ior;
          m.iridescence_thickness = nm.params.iridescence_thickness;
        }
        m.notes = unrendered(nm);
        apply_texture_means(nm, m);
        s.materials.push_back(m);
      }
      if (s.materials.empty()) throw Error(s.materials_file + ": no materials");
    }
  }
  // What a target's split-sum shader does not honour of a rendered extension (the reference does).
  for (PreviewMaterial& m : s.materials) {
    auto note = [&m](const std::string& text) {
      if (std::find(m.notes.begin(), m.notes.end(), text) == m.notes.end()) m.notes.push_back(text);
    };
    if (s.target == EngineTarget::Filament && m.specular != 1.0 && m.metallic < 1.0)
      note("KHR_materials_specular: filament's split-sum scales F0 by specularFactor, F90 stays 1 (specularDFG)");
    if ((s.target == EngineTarget::Gltf || s.target == EngineTarget::Babylon) && m.clearcoat > 0.0)
      note(
          "KHR_materials_clearcoat: in the split-sum render, Babylon.js's clear coat block (pbrBlockClearcoat.fx, the "
          "glTF loader's options): the reflection texture at getLodFromAlphaG(clearcoatRoughness^2 + 0.0005) x "
          "clearcoat mix(x, y, 0.04) of the DFG table at (n.v, clearcoatRoughness), the rest x 1 - clearcoat "
          "F_Schlick(0.04, 1, n.v); the base's R0 not remapped (remapF0OnInterfaceChange false)");
    // KHR_materials_sheen: noted once the bake is read (render_preview: SplitSum::sheen_note)
  }
  if (s.materials.size() > size_t(kPreviewMaxSpheres))
    throw Error(std::to_string(s.materials.size()) + " materials: at most " + std::to_string(kPreviewMaxSpheres));
  for (const PreviewMaterial& m : s.materials) {
    const double c[3] = {m.base_color.r, m.base_color.g, m.base_color.b};
    for (double v : c)
      if (!(v >= 0.0 && v <= 1.0)) throw Error("material '" + m.name + "': baseColor must be in [0, 1]");
    if (!(m.metallic >= 0.0 && m.metallic <= 1.0)) throw Error("material '" + m.name + "': metallic must be in [0, 1]");
    if (!(m.roughness >= 0.0 && m.roughness <= 1.0))
      throw Error("material '" + m.name + "': roughness must be in [0, 1]");
    if (!(m.ior == 0.0 || (m.ior >= 1.0 && std::isfinite(m.ior))))
      throw Error("material '" + m.name + "': ior must be 0 or a finite number >= 1");
    if (!(m.specular >= 0.0 && m.specular <= 1.0)) throw Error("material '" + m.name + "': specular must be in [0, 1]");
    if (!(m.clearcoat >= 0.0 && m.clearcoat <= 1.0))
      throw Error("material '" + m.name + "': clearcoat must be in [0, 1]");
    if (!(m.clearcoat_roughness >= 0.0 && m.clearcoat_roughness <= 1.0))
      throw Error("material '" + m.name + "': clearcoat_roughness must be in [0, 1]");
    if (!(m.sheen_roughness >= 0.0 && m.sheen_roughness <= 1.0))
      throw Error("material '" + m.name + "': sheen_roughness must be in [0, 1]");
    if (!(m.iridescence >= 0.0 && m.iridescence <= 1.0))
      throw Error("material '" + m.name + "': iridescence must be in [0, 1]");
    if (!(m.iridescence_ior >= 1.0 && m.iridescence_ior <= 10.0))
      throw Error("material '" + m.name + "': iridescence_ior must be in [1, 10]");
    if (!(m.iridescence_thickness >= 0.0 && m.iridescence_thickness <= 1e5))
      throw Error("material '" + m.name + "': iridescence_thickness must be in [0, 100000] nm");
    for (double v : {m.sheen_color.r, m.sheen_color.g, m.sheen_color.b})
      if (!(v >= 0.0 && v <= 1.0)) throw Error("material '" + m.name + "': sheen_color must be in [0, 1]");
    for (double v : {m.specular_color.r, m.specular_color.g, m.specular_color.b})
      if (!(v >= 0.0 && std::isfinite(v)))
        throw Error("material '" + m.name + "': specular_color must be finite and >= 0");
  }
  const int n = int(s.materials.size());
  if (s.columns <= 0) {
    // square cells: columns / rows close to width / height
    s.columns = std::max(1, int(std::ceil(std::sqrt(double(n) * s.width / s.height))));
  }
  s.columns = std::min(s.columns, n);
  const int rows = (n + s.columns - 1) / s.columns;
  if (s.width / s.columns < 8 || s.height / rows < 8)
    throw Error(std::to_string(n) + " spheres in " + std::to_string(s.columns) +
                " columns leave cells under 8 pixels in a " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                " image: give a larger image");
  if (!(s.refinement >= 1.0 && s.refinement <= kPreviewMaxRefinement)) throw Error("refinement must be in 1..64");
  if (!(s.bound_goal >= 0.0 && s.bound_goal <= 1.0)) throw Error("bound_goal must be in 0..1");
  if (s.bound_stride < 1) throw Error("bound_stride must be at least 1");
  return s;
}

double material_alpha(const PreviewMaterial& m) { return m.roughness * m.roughness; }

Layout make_layout(const PreviewSpec& s) {
  Layout l;
  l.width = s.width;
  l.height = s.height;
  // The camera: yaw about +Y, then pitch about the turned right axis.
  PreviewCamera& c = l.camera;
  c.yaw = s.yaw;
  c.pitch = s.pitch;
  const double yaw = s.yaw * M_PI / 180.0, pitch = s.pitch * M_PI / 180.0;
  const Vec3 d0 = rotate_y({0.0, 0.0, -1.0}, yaw), r0 = rotate_y({1.0, 0.0, 0.0}, yaw);
  const Vec3 u0{0.0, 1.0, 0.0};
  c.view_direction =
      normalized({d0.x * std::cos(pitch) + u0.x * std::sin(pitch), d0.y * std::cos(pitch) + u0.y * std::sin(pitch),
                  d0.z * std::cos(pitch) + u0.z * std::sin(pitch)});
  c.up = normalized({u0.x * std::cos(pitch) - d0.x * std::sin(pitch), u0.y * std::cos(pitch) - d0.y * std::sin(pitch),
                     u0.z * std::cos(pitch) - d0.z * std::sin(pitch)});
  c.right = r0;
  const int n = int(s.materials.size());
  const int rows = (n + s.columns - 1) / s.columns;
  const double cw = double(s.width) / s.columns, ch = double(s.height) / rows;
  const double radius = 0.46 * std::min(cw, ch);
  for (int i = 0; i < n; ++i) {
    PreviewSphere sp;
    sp.material = s.materials[size_t(i)];
    sp.row = i / s.columns;
    sp.column = i % s.columns;
    sp.centre_x = std::floor((sp.column + 0.5) * cw);
    sp.centre_y = std::floor((sp.row + 0.5) * ch);
    sp.radius = radius;
    l.spheres.push_back(sp);
  }
  return l;
}

Vec3 view_vector(const PreviewCamera& c) { return {-c.view_direction.x, -c.view_direction.y, -c.view_direction.z}; }

std::vector<SpherePixel> sphere_pixels(const Layout& l) {
  std::vector<SpherePixel> out;
  const PreviewCamera& c = l.camera;
  const Vec3 v = view_vector(c);
  for (size_t s = 0; s < l.spheres.size(); ++s) {
    const PreviewSphere& sp = l.spheres[s];
    const int x0 = std::max(0, int(std::floor(sp.centre_x - sp.radius))),
              x1 = std::min(l.width - 1, int(std::ceil(sp.centre_x + sp.radius)));
    const int y0 = std::max(0, int(std::floor(sp.centre_y - sp.radius))),
              y1 = std::min(l.height - 1, int(std::ceil(sp.centre_y + sp.radius)));
    // the normal at a pixel centre in the camera's (right, -up, v) frame; false off the sphere
    auto normal_at = [&](int x, int y, double n[3]) {
      const double dx = (x + 0.5 - sp.centre_x) / sp.radius, dy = (y + 0.5 - sp.centre_y) / sp.radius;
      const double d2 = dx * dx + dy * dy;
      if (!(d2 < 1.0)) return false;
      n[0] = dx, n[1] = dy, n[2] = std::sqrt(1.0 - d2);
      return true;
    };
    auto dist2 = [](const double a[3], const double b[3]) {
      return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
    };
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double dx = (x + 0.5 - sp.centre_x) / sp.radius, dy = (y + 0.5 - sp.centre_y) / sp.radius;
        const double d2 = dx * dx + dy * dy;
        if (!(d2 < 1.0)) continue;
        const double nz = std::sqrt(1.0 - d2);
        SpherePixel p;
        double q00[3], q10[3], q01[3], q11[3];
        const int qx = x & ~1, qy = y & ~1;
        if (normal_at(qx, qy, q00) && normal_at(qx + 1, qy, q10) && normal_at(qx, qy + 1, q01) &&
            normal_at(qx + 1, qy + 1, q11))
          p.normal_slope2 = std::max(dist2(q10, q00), dist2(q01, q00));
        else  // d n / d x = (right - (dx / nz) v) / radius, likewise in y
          p.normal_slope2 = (1.0 + std::max(dx * dx, dy * dy) / std::max(nz * nz, 1e-12)) / (sp.radius * sp.radius);
        p.x = x;
        p.y = y;
        p.sphere = int(s);
        p.n = normalized({dx * c.right.x - dy * c.up.x + nz * v.x, dx * c.right.y - dy * c.up.y + nz * v.y,
                          dx * c.right.z - dy * c.up.z + nz * v.z});
        p.n_dot_v = nz;
        out.push_back(p);
      }
  }
  return out;
}

Vec3 background_direction(const Layout& l, int x, int y) {
  const PreviewCamera& c = l.camera;
  const double t = std::tan(0.5 * c.background_fov * M_PI / 180.0);
  const double a = (x + 0.5 - 0.5 * l.width) / (0.5 * l.height) * t,
               b = (y + 0.5 - 0.5 * l.height) / (0.5 * l.height) * t;
  return normalized({c.view_direction.x + a * c.right.x - b * c.up.x, c.view_direction.y + a * c.right.y - b * c.up.y,
                     c.view_direction.z + a * c.right.z - b * c.up.z});
}

}  // namespace detail::preview
}  // namespace brdfbake
