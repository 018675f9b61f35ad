// render_preview (brdfbake/preview.hpp): the bake, the split-sum render, the reference render and
// the error between them.
#include "families/preview/render.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <thread>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "brdfbake/plan.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/ideal.hpp"
#include "families/preview/iridescence.hpp"
#include "families/preview/kernel.hpp"
#include "families/preview/model.hpp"
#include "families/preview/shading.hpp"
#include "families/preview/splitsum.hpp"
#include "text.hpp"
#include "view/canvas.hpp"

namespace brdfbake {

namespace detail::preview {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double luminance(const float* rgb) {
  return 0.2126 * double(rgb[0]) + 0.7152 * double(rgb[1]) + 0.0722 * double(rgb[2]);
}

// A folder in `base` (the system's temporary directory when empty), removed with everything in it
// on destruction. Hidden and named with the process id, as the staging folders are.
class TempFolder {
 public:
  explicit TempFolder(const std::string& base) {
    static std::atomic<int> counter{0};
    path_ = (base.empty() ? fs::temp_directory_path() : fs::path(base)) /
            (".brdfbake-preview-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(path_);
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  std::string path() const { return path_.string(); }

 private:
  fs::path path_;
};

// Bakes first_bake_plan's job into `folder`, on the same backend.
void bake_first(Backend& backend, const EnvImage& env, EngineTarget target, const std::string& folder, bool sheen,
                const PreviewProgress& progress) {
  try {
    check_environment_source(env.source);
  } catch (const Error& e) {
    throw Error(std::string("the preview bakes first from the environment's source, which it cannot open (") +
                e.what() + "): give a bake folder (bake)");
  }
  Plan plan = first_bake_plan(env, target, sheen);
  plan.job.output_dir = folder;
  plan.job.engine_name = "preview";  // not the scratch folder's name: the JSON names the files
  RunOptions ro;
  ro.backend = [&backend](const std::string&) { return std::shared_ptr<Backend>(&backend, [](Backend*) {}); };
  run_job(
      plan.job,
      [&](const JobEvent& e) {
        if (progress) progress(0.1 * (e.bake + e.fraction) / std::max(1, e.bakes), "bake: " + e.what);
      },
      ro);
}

// The environment's radiance in direction d under the reference's model (the constant cell d
// falls in).
Rgb equirect_cell(const EnvImage& e, const Vec3& d) {
  double u = 0, v = 0;
  math::equirect_coords(d, u, v);
  const int x = std::clamp(int(std::floor(u * e.width)), 0, e.width - 1);
  const int y = std::clamp(int(std::floor(v * e.height)), 0, e.height - 1);
  const float* p = &e.rgb[3 * (size_t(y) * size_t(e.width) + size_t(x))];
  return {p[0], p[1], p[2]};
}

void put(PreviewImage& img, int x, int y, const Rgb& c) {
  float* p = &img.rgb[3 * (size_t(y) * size_t(img.width) + size_t(x))];
  p[0] = float(c.r);
  p[1] = float(c.g);
  p[2] = float(c.b);
}

double rgb_norm(const float* a) {
  const double x = a[0], y = a[1], z = a[2];
  return std::sqrt(x * x + y * y + z * z);
}
double rgb_distance(const float* a, const float* b) {
  const double d[3] = {double(a[0]) - double(b[0]), double(a[1]) - double(b[1]), double(a[2]) - double(b[2])};
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}
// The relative rounding of the reference's float sums, below which no bound is stated.
constexpr double kFloatSumFloor = 1e-6;

double relative(const double* a, const double* b) {
  const double d =
      std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
  const double n = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  return n > 0.0 ? d / n : (d > 0.0 ? 1.0 : 0.0);
}

// A default grid's sphere's group: its row's material ("gold r0.5" is "gold").
std::string group_of(const std::string& name) {
  const size_t at = name.rfind(" r");
  if (at == std::string::npos || at + 2 >= name.size()) return name;
  for (size_t k = at + 2; k < name.size(); ++k)
    if (!(std::isdigit(static_cast<unsigned char>(name[k])) || name[k] == '.')) return name;
  return name.substr(0, at);
}

double median_of(std::vector<double> x) {
  if (x.empty()) return 0.0;
  std::sort(x.begin(), x.end());
  return x[x.size() / 2];
}

}  // namespace

Plan first_bake_plan(const EnvImage& env, EngineTarget target, bool sheen, PlanOptions o) {
  o.environment = env.source;
  o.sanitize = env.sanitize.replaced;
  o.target = engine_target_name(target);
  if (!sheen) return plan_default(o);
  Scene scene;
  scene.path = "the preview's sheened materials";
  SceneMaterial m;
  m.label = "sheen";
  m.metallic = 0.0;
  m.sheen = true;
  m.sheen_color = {1.0, 1.0, 1.0};
  m.sheen_roughness = 1.0;
  m.sheen_roughness_texture = true;  // the range 0..1
  scene.materials.push_back(m);
  return plan_scene(scene, o);
}

EnvImage reference_equirect(const EnvImage& env) {
  if (env.layout == EnvImage::Layout::Equirect) return env;
  EnvImage e;
  e.layout = EnvImage::Layout::Equirect;
  e.width = 4 * env.width;
  e.height = 2 * env.width;
  e.source = env.source;
  e.description = env.description + ", resampled to a " + std::to_string(e.width) + "x" + std::to_string(e.height) +
                  " equirect (nearest texel)";
  e.rgb.resize(3 * size_t(e.width) * size_t(e.height));
  const int s = env.width;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      const Vec3 d = math::equirect_direction((x + 0.5) / e.width, (y + 0.5) / e.height);
      int face = 0;
      double a = 0, b = 0;
      math::cube_face_coords(d, face, a, b);
      const int i = std::clamp(int(std::floor(0.5 * (a + 1.0) * s)), 0, s - 1);
      const int j = std::clamp(int(std::floor(0.5 * (b + 1.0) * s)), 0, s - 1);
      const float* p = &env.rgb[3 * ((size_t(face) * size_t(s) + size_t(j)) * size_t(s) + size_t(i))];
      std::copy(p, p + 3, &e.rgb[3 * (size_t(y) * size_t(e.width) + size_t(x))]);
    }
  return e;
}

double median_luminance(const EnvImage& e) {
  // Solid-angle weights (cos(latitude) per row) into a histogram of log2 luminance with 1/128 EV
  // bins between the smallest positive and the largest value (linear time: a sort of the 512k
  // pixels of a 1k map took 0.1 s); black pixels count below every bin. The median to 0.01 EV is
  // what the sheet's exposure needs.
  constexpr double kBinsPerEv = 128.0;
  double lo = HUGE_VAL, hi = 0.0, total = 0.0, black = 0.0;
  for (size_t i = 0; i < e.rgb.size() / 3; ++i) {
    const double l = luminance(&e.rgb[3 * i]);
    if (l > 0.0) {
      lo = std::min(lo, l);
      hi = std::max(hi, l);
    }
  }
  if (!(hi > 0.0)) return 0.0;
  const double l0 = std::log2(lo);
  const size_t bins = size_t(std::ceil((std::log2(hi) - l0) * kBinsPerEv)) + 1;
  std::vector<double> h(bins, 0.0);
  for (int y = 0; y < e.height; ++y) {
    const double w = std::cos(M_PI * (0.5 - (y + 0.5) / e.height));
    for (int x = 0; x < e.width; ++x) {
      const double l = luminance(&e.rgb[3 * (size_t(y) * size_t(e.width) + size_t(x))]);
      total += w;
      if (l > 0.0)
        h[std::min(bins - 1, size_t((std::log2(l) - l0) * kBinsPerEv))] += w;
      else
        black += w;
    }
  }
  double acc = black;
  if (acc >= 0.5 * total) return 0.0;
  for (size_t b = 0; b < bins; ++b) {
    acc += h[b];
    if (acc >= 0.5 * total) return std::exp2(l0 + (double(b) + 0.5) / kBinsPerEv);
  }
  return hi;
}

PreviewErrorStats error_stats(std::vector<double> e) {
  PreviewErrorStats s;
  if (e.empty()) return s;
  double sum2 = 0.0;
  for (double x : e) sum2 += x * x;
  s.rms = std::sqrt(sum2 / double(e.size()));
  std::sort(e.begin(), e.end());
  s.p99 = e[(e.size() - 1) * 99 / 100];
  s.max = e.back();
  return s;
}

ReferenceBound reference_bound(const std::vector<double>& differences) {
  const PreviewErrorStats d = error_stats(differences);
  ReferenceBound b;
  b.rms = kPreviewBoundFactor * d.rms + kPreviewBoundFloor;
  b.max = kPreviewBoundFactor * d.max + kPreviewBoundFloor;
  return b;
}

std::vector<PreviewSphereStats> sphere_errors(const Layout& layout, const std::vector<SpherePixel>& pixels,
                                              const PreviewImage& splitsum, const PreviewImage& reference,
                                              double exposure) {
  ViewOptions vo;
  vo.exposure = exposure;
  std::vector<std::vector<double>> lin(layout.spheres.size()), steps(layout.spheres.size());
  for (const SpherePixel& p : pixels) {
    const size_t at = 3 * (size_t(p.y) * size_t(layout.width) + size_t(p.x));
    const float* s = &splitsum.rgb[at];
    const float* r = &reference.rgb[at];
    const double n = rgb_norm(r), d = rgb_distance(s, r);
    lin[size_t(p.sphere)].push_back(n > 0.0 ? d / n : (d > 0.0 ? 1.0 : 0.0));
    const view::Rgb8 a = view::tone_map(s, vo), b = view::tone_map(r, vo);
    int worst = 0;
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(a[size_t(c)]) - int(b[size_t(c)])));
    steps[size_t(p.sphere)].push_back(worst);
  }
  std::vector<PreviewSphereStats> out(layout.spheres.size());
  for (size_t s = 0; s < out.size(); ++s) {
    out[s].pixels = int(lin[s].size());
    out[s].linear = error_stats(lin[s]);
    out[s].srgb8 = error_stats(steps[s]);
  }
  return out;
}

std::vector<PreviewShareGroup> share_groups(const PreviewResult& r) {
  // the default grid by its rows; any other list of materials by sphere
  const std::vector<PreviewMaterial> grid = preview_default_materials();
  bool rows = grid.size() == r.spheres.size();
  for (size_t k = 0; rows && k < grid.size(); ++k) rows = grid[k].name == r.spheres[k].material.name;
  std::vector<PreviewShareGroup> groups;
  for (size_t k = 0; k < r.spheres.size() && k < r.stats.size(); ++k) {
    const std::string name = rows ? group_of(r.spheres[k].material.name) : r.spheres[k].material.name;
    auto g = std::find_if(groups.begin(), groups.end(), [&](const PreviewShareGroup& x) { return x.name == name; });
    if (g == groups.end()) {
      groups.push_back({});
      g = groups.end() - 1;
      g->name = name;
    }
    g->spheres.push_back(int(k));
  }
  for (PreviewShareGroup& g : groups) {
    std::vector<double> total, engine, bake;
    for (int k : g.spheres) {
      total.push_back(r.stats[size_t(k)].linear.rms);
      engine.push_back(r.stats[size_t(k)].engine_share.rms);
      bake.push_back(r.stats[size_t(k)].bake_share.rms);
    }
    g.error_median = median_of(total);
    g.error_worst = *std::max_element(total.begin(), total.end());
    g.engine_median = median_of(engine);
    g.engine_worst = *std::max_element(engine.begin(), engine.end());
    g.bake_median = median_of(bake);
    g.bake_worst = *std::max_element(bake.begin(), bake.end());
  }
  return groups;
}

}  // namespace detail::preview

namespace detail::preview {

// The split-sum render into `out`: the background (the bake's level 0, or grey) and each sphere pixel
// shaded as the target's shader does from the bake's files.
void render_split_sum(const Layout& layout, const std::vector<SpherePixel>& pixels, const SplitSum& split,
                      const Vec3& v, const PreviewResult& res, PreviewImage& out) {
  const bool grey = res.spec.background == PreviewBackground::Grey;
  out.width = layout.width;
  out.height = layout.height;
  out.rgb.assign(3 * size_t(layout.width) * size_t(layout.height), 0.18f);
  if (!grey)
    for (int y = 0; y < layout.height; ++y)
      for (int x = 0; x < layout.width; ++x) put(out, x, y, split.sky(background_direction(layout, x, y)));
  for (const SpherePixel& p : pixels)
    put(out, p.x, p.y, split.shade(p.n, v, res.spheres[size_t(p.sphere)].material, float(p.normal_slope2)));
}

std::vector<double> sharp_probe(const Layout& layout, const SplitSum& files, const SplitSum& ideal, int samples) {
  const PreviewCamera& c = layout.camera;
  const Vec3 v = view_vector(c);
  const double radius = 2.0 * std::max(files.files().specular.size, 1);
  const int across = int(2.0 * radius);
  std::vector<double> out(layout.spheres.size(), -1.0);
  std::vector<size_t> probed;
  for (size_t s = 0; s < layout.spheres.size(); ++s)
    if (layout.spheres[s].material.roughness < kProbeMaxRoughness) probed.push_back(s);
  // The spheres shared among the machine's cores (SplitSum::shade reads only).
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t at = next++; at < probed.size(); at = next++) {
      const size_t s = probed[at];
      const PreviewMaterial& m = layout.spheres[s].material;
      double sum = 0.0;
      int n = 0;
      // The pixels of a sphere of `radius` centred on a pixel corner: the R2 sequence (Roberts 2018) over
      // the square around it, each point taken to its pixel's centre, those off the disc skipped.
      constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
      for (long k = 0; n < samples && k < 4L * samples; ++k) {
        const double u = std::fmod(0.5 + a1 * double(k), 1.0), w = std::fmod(0.5 + a2 * double(k), 1.0);
        const int px = std::min(across - 1, int(u * across)), py = std::min(across - 1, int(w * across));
        const double dx = (px + 0.5 - radius) / radius, dy = (py + 0.5 - radius) / radius;
        const double d2 = dx * dx + dy * dy;
        if (!(d2 < 1.0)) continue;
        const double nz = std::sqrt(1.0 - d2);
        Vec3 normal{dx * c.right.x - dy * c.up.x + nz * v.x, dx * c.right.y - dy * c.up.y + nz * v.y,
                    dx * c.right.z - dy * c.up.z + nz * v.z};
        const double length = std::sqrt(math::dot(normal, normal));
        normal = {normal.x / length, normal.y / length, normal.z / length};
        // the analytic normal slope of sphere_pixels' rim (Babylon.js's specular anti-aliasing)
        const float slope2 = float((1.0 + std::max(dx * dx, dy * dy) / std::max(nz * nz, 1e-12)) / (radius * radius));
        const Rgb f = files.shade(normal, v, m, slope2), i = ideal.shade(normal, v, m, slope2);
        const float fa[3] = {float(f.r), float(f.g), float(f.b)}, ia[3] = {float(i.r), float(i.g), float(i.b)};
        const double norm = rgb_norm(ia), d = rgb_distance(fa, ia);
        const double rel = std::min(kProbeMaxPixelError, norm > 0.0 ? d / norm : (d > 0.0 ? 1.0 : 0.0));
        sum += rel * rel;
        ++n;
      }
      if (n > 0) out[s] = std::sqrt(sum / n);
    }
  };
  std::vector<std::thread> threads;
  const unsigned cores = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  for (unsigned t = 1; t < cores && t < probed.size(); ++t) threads.emplace_back(work);
  work();
  for (auto& t : threads) t.join();
  return out;
}

namespace {

// The sheet's exposure: 0.18 / the environment's median (a sun map is not white), lowered where
// that would put the spheres' median luminance above 0.8 (a dark studio lit by small softboxes:
// its median is 0.009, and +4.4 EV turned every sphere white).
double sheet_exposure(const PreviewResult& res, const std::vector<SpherePixel>& pixels, int width) {
  double exposure =
      res.environment_median > 0.0 ? std::clamp(std::log2(0.18 / res.environment_median), -30.0, 30.0) : 0.0;
  std::vector<double> lum;
  for (const SpherePixel& p : pixels)
    lum.push_back(luminance(&res.splitsum.rgb[3 * (size_t(p.y) * size_t(width) + size_t(p.x))]));
  if (!lum.empty()) {
    std::nth_element(lum.begin(), lum.begin() + std::ptrdiff_t(lum.size() / 2), lum.end());
    const double m = lum[lum.size() / 2];
    if (m > 0.0) exposure = std::min(exposure, std::log2(0.8 / m));
  }
  return exposure;
}

constexpr size_t kNoLobe = size_t(-1);

// A pixel's iridescent films' entries (KHR_materials_iridescence): the dielectric's and the metal's,
// kNoLobe where the material has no such film.
struct FilmEntries {
  size_t dielectric = size_t(-1), metal = size_t(-1);
};

// A pixel's reference radiance from its entries (the base t, the coat c, the sheen h and the films f,
// kNoLobe where the material has no such lobe) of `entries` and their integrals `values` (9 an entry).
Rgb lobes_radiance(const TargetBrdf& brdf, const PreviewMaterial& m, double n_dot_v,
                   const std::vector<ReferencePixel>& entries, const std::vector<double>& values, size_t t, size_t c,
                   size_t h, const FilmEntries& f = {}) {
  return reference_radiance(brdf, m, entries[t].albedo, entries[t].bias, &values[9 * t], n_dot_v,
                            c == kNoLobe ? nullptr : &values[9 * c], h == kNoLobe ? nullptr : &values[9 * h],
                            h == kNoLobe ? 0.0 : double(entries[h].albedo),
                            f.dielectric == kNoLobe ? nullptr : &values[9 * f.dielectric],
                            f.metal == kNoLobe ? nullptr : &values[9 * f.metal]);
}

// The reference's work: each distinct (normal, alpha) once, with the exact albedos at its n.v and
// roughness, and the bound's pixels (each distinct one once more, at twice the refinement).
struct ReferenceWork {
  ReferenceTask task;
  std::vector<size_t> task_of;        // per sphere pixel: its entry of task.pixels
  std::vector<size_t> bound_index;    // the sphere pixels the bound is measured on
  std::vector<size_t> bound_task_of;  // per bound pixel: its entry of task.bound_pixels
  // The clear coat's lobe (KHR_materials_clearcoat): per sphere pixel and per bound pixel, the entry
  // of the same normal at the coat's alpha (kNoLobe for an uncoated sphere).
  std::vector<size_t> coat_task_of, bound_coat_task_of;
  // The sheen lobe (KHR_materials_sheen): likewise, the entry of the same normal's Charlie lobe at the
  // sheen's alpha (kNoLobe for a sphere without sheen).
  std::vector<size_t> sheen_task_of, bound_sheen_task_of;
  // The iridescent films (KHR_materials_iridescence): likewise, the entries of the same normal's GGX
  // lobe times the thin film over the dielectric's and the metal's F0.
  std::vector<FilmEntries> film_task_of, bound_film_task_of;
  double lut_seconds = 0.0;
};

// The exact albedo tables the reference's lobes look up (albedo_tables).
struct AlbedoTables {
  std::vector<double> nvs, rs, ab;  // n.v, roughness; (albedo, bias) pairs, roughness-major
  std::vector<double> srs, es;      // sheen roughness; E(n.v), sheen-roughness-major
};

AlbedoTables albedo_tables(Backend& backend, const PreviewResult& res, const std::vector<SpherePixel>& pixels,
                           double* lut_seconds) {
  AlbedoTables t;
  // The exact albedos at every pixel's n.v (every sphere covers the same offsets) and roughness.
  std::set<double> nv_set, r_set;
  for (const SpherePixel& p : pixels) nv_set.insert(std::max(p.n_dot_v, 1e-7));
  for (const PreviewSphere& s : res.spheres) {
    r_set.insert(s.material.roughness);
    if (s.material.clearcoat > 0.0) r_set.insert(s.material.clearcoat_roughness);
  }
  t.nvs.assign(nv_set.begin(), nv_set.end());
  t.rs.assign(r_set.begin(), r_set.end());
  t.ab = t.nvs.empty() ? std::vector<double>() : exact_albedos(backend, t.nvs, t.rs, lut_seconds);
  // The sheen lobes' exact albedos E(n.v) at their sheen roughnesses (the charlie table's quadrature).
  std::set<double> sheen_set;
  for (const PreviewSphere& s : res.spheres)
    if (preview_has_sheen(s.material)) sheen_set.insert(s.material.sheen_roughness);
  t.srs.assign(sheen_set.begin(), sheen_set.end());
  double sheen_seconds = 0.0;
  t.es = t.nvs.empty() || t.srs.empty() ? std::vector<double>() : sheen_albedos(backend, t.nvs, t.srs, &sheen_seconds);
  *lut_seconds += sheen_seconds;
  return t;
}

// The GGX lobe of a pixel's normal at `roughness`, with its exact albedo and bias.
ReferencePixel ggx_pixel(const AlbedoTables& t, const SpherePixel& p, double roughness) {
  ReferencePixel r;
  r.n[0] = float(p.n.x);
  r.n[1] = float(p.n.y);
  r.n[2] = float(p.n.z);
  r.alpha = float(roughness * roughness);
  const size_t i = size_t(std::lower_bound(t.nvs.begin(), t.nvs.end(), std::max(p.n_dot_v, 1e-7)) - t.nvs.begin());
  const size_t j = size_t(std::lower_bound(t.rs.begin(), t.rs.end(), roughness) - t.rs.begin());
  const double a = t.ab[2 * (j * t.nvs.size() + i)];
  const double b = t.ab[2 * (j * t.nvs.size() + i) + 1];
  r.albedo = float(a);
  r.bias = float(b);
  return r;
}

// The sheen (Charlie) lobe of a pixel's normal at the sheen roughness.
ReferencePixel sheen_pixel(const AlbedoTables& t, const SpherePixel& p, double roughness) {
  ReferencePixel r;
  r.n[0] = float(p.n.x);
  r.n[1] = float(p.n.y);
  r.n[2] = float(p.n.z);
  r.alpha = float(preview_sheen_alpha(roughness));
  const size_t i = size_t(std::lower_bound(t.nvs.begin(), t.nvs.end(), std::max(p.n_dot_v, 1e-7)) - t.nvs.begin());
  const size_t j = size_t(std::lower_bound(t.srs.begin(), t.srs.end(), roughness) - t.srs.begin());
  r.albedo = float(t.es[j * t.nvs.size() + i]);
  r.bias = 0.0f;
  r.sheen = true;
  return r;
}

// The GGX lobe at the material's roughness times the thin film over base_f0 (the walk's
// normalisation: the GGX lobe's A, and no S2).
ReferencePixel film_pixel(const AlbedoTables& t, const SpherePixel& p, const PreviewMaterial& m, const Rgb& base_f0) {
  ReferencePixel r = ggx_pixel(t, p, m.roughness);
  r.bias = 0.0f;
  r.film = true;
  r.film_thickness = float(m.iridescence_thickness);
  r.film_ior = float(m.iridescence_ior);
  r.film_base_f0[0] = float(base_f0.r);
  r.film_base_f0[1] = float(base_f0.g);
  r.film_base_f0[2] = float(base_f0.b);
  return r;
}

// Every pixel's lobes as task entries. The integrals depend on the normal and alpha only (the colours
// enter in reference_radiance), and every sphere covers the same normals: each distinct (n, alpha) is
// integrated once (the default grid's 72 spheres are 12 roughnesses).
void add_lobes(ReferenceWork& w, const AlbedoTables& t, const PreviewResult& res,
               const std::vector<SpherePixel>& pixels) {
  ReferenceTask& task = w.task;
  // (n, alpha, the lobe: 0 GGX, 1 sheen, 2 film; the film's thickness, index and base F0)
  std::map<std::array<float, 10>, size_t> unique;
  auto entry = [&](const ReferencePixel& r) {
    const std::array<float, 10> key = {r.n[0],
                                       r.n[1],
                                       r.n[2],
                                       r.alpha,
                                       r.film    ? 2.0f
                                       : r.sheen ? 1.0f
                                                 : 0.0f,
                                       r.film_thickness,
                                       r.film_ior,
                                       r.film_base_f0[0],
                                       r.film_base_f0[1],
                                       r.film_base_f0[2]};
    const auto [it, added] = unique.emplace(key, task.pixels.size());
    if (added) task.pixels.push_back(r);
    return it->second;
  };
  w.task_of.resize(pixels.size());
  w.coat_task_of.assign(pixels.size(), kNoLobe);
  w.sheen_task_of.assign(pixels.size(), kNoLobe);
  w.film_task_of.assign(pixels.size(), FilmEntries{});
  for (size_t i = 0; i < pixels.size(); ++i) {
    const PreviewMaterial& m = res.spheres[size_t(pixels[i].sphere)].material;
    w.task_of[i] = entry(ggx_pixel(t, pixels[i], m.roughness));
    if (m.clearcoat > 0.0) w.coat_task_of[i] = entry(ggx_pixel(t, pixels[i], m.clearcoat_roughness));
    if (preview_has_sheen(m)) w.sheen_task_of[i] = entry(sheen_pixel(t, pixels[i], m.sheen_roughness));
    const ReferenceFilms films = reference_films(m);
    if (films.dielectric_weight > 0.0)
      w.film_task_of[i].dielectric = entry(film_pixel(t, pixels[i], m, films.dielectric_f0));
    if (films.metal_weight > 0.0) w.film_task_of[i].metal = entry(film_pixel(t, pixels[i], m, films.metal_f0));
  }
}

// The bound's pixels: every bound_stride-th of each sphere, at least 16 (or all) a sphere; each
// distinct one integrated once more at twice the refinement.
void add_bound_pixels(ReferenceWork& w, const PreviewResult& res, const std::vector<SpherePixel>& pixels) {
  ReferenceTask& task = w.task;
  std::vector<std::vector<size_t>> of_sphere(res.spheres.size());
  for (size_t i = 0; i < pixels.size(); ++i) of_sphere[size_t(pixels[i].sphere)].push_back(i);
  std::map<size_t, size_t> bound_unique;
  auto bound_entry = [&](size_t t) {
    const auto [it, added] = bound_unique.emplace(t, task.bound_pixels.size());
    if (added) task.bound_pixels.push_back(task.pixels[t]);
    return it->second;
  };
  for (const auto& list : of_sphere) {
    const size_t n = list.size();
    const size_t stride = std::max<size_t>(1, std::min<size_t>(size_t(res.spec.bound_stride), n / 16));
    for (size_t k = stride / 2; k < n; k += stride) {
      w.bound_index.push_back(list[k]);
      w.bound_task_of.push_back(bound_entry(w.task_of[list[k]]));
      const size_t c = w.coat_task_of[list[k]];
      w.bound_coat_task_of.push_back(c == kNoLobe ? kNoLobe : bound_entry(c));
      const size_t h = w.sheen_task_of[list[k]];
      w.bound_sheen_task_of.push_back(h == kNoLobe ? kNoLobe : bound_entry(h));
      const FilmEntries& f = w.film_task_of[list[k]];
      w.bound_film_task_of.push_back({f.dielectric == kNoLobe ? kNoLobe : bound_entry(f.dielectric),
                                      f.metal == kNoLobe ? kNoLobe : bound_entry(f.metal)});
    }
  }
}

ReferenceWork reference_work(Backend& backend, const PreviewResult& res, const std::vector<SpherePixel>& pixels) {
  ReferenceWork w;
  const AlbedoTables tables = albedo_tables(backend, res, pixels, &w.lut_seconds);
  add_lobes(w, tables, res, pixels);
  add_bound_pixels(w, res, pixels);
  return w;
}

// The reference image's background: the environment's cells, or grey.
void fill_background(const EnvImage& equirect, const Layout& layout, PreviewResult& res) {
  res.reference.width = layout.width;
  res.reference.height = layout.height;
  res.reference.rgb.assign(res.splitsum.rgb.size(), 0.18f);
  if (res.spec.background == PreviewBackground::Grey) return;
  for (int y = 0; y < layout.height; ++y)
    for (int x = 0; x < layout.width; ++x)
      put(res.reference, x, y, equirect_cell(equirect, background_direction(layout, x, y)));
}

// One pass of the reference over `pixels` (a subset of the spheres' pixels: index[k] is pixels[k]'s
// place in the whole list) at a refinement: each pixel's radiance into `ref` and the image, and the
// bound's relative differences per sphere into `bound` (those of the pass's spheres replaced).
void reference_pass(Backend& backend, const EnvImage& equirect, const std::vector<SpherePixel>& pixels,
                    const std::vector<size_t>& index, const TargetBrdf& brdf, const Vec3& v, double refinement,
                    const std::function<void(double)>& progress, PreviewResult& res, std::vector<Rgb>& ref,
                    std::vector<std::vector<double>>& bound) {
  ReferenceWork w = reference_work(backend, res, pixels);
  ReferenceTask& task = w.task;
  task.environment = &equirect;
  task.view = v;
  task.refinement = refinement;
  task.radiance_scale = M_PI * std::max(res.environment_median, 1e-30);
  task.precision = res.spec.precision;
  const detail::ReferenceSums sums = detail::run_preview_reference(backend, task, progress);
  res.times.reference += sums.wall_seconds;
  res.times.reference_device += sums.device_seconds + w.lut_seconds;
  res.times.bound += sums.bound_wall_seconds;
  res.bound_definition =
      "per sphere, " + std::to_string(int(kPreviewBoundFactor)) + " x the RMS (and max) over its bound pixels (every " +
      std::to_string(res.spec.bound_stride) +
      "th, at least 16) of |reference - reference at twice the refinement| / |reference at twice the refinement| "
      "(RGB norms), plus " +
      fmt_number(100.0 * kPreviewBoundFloor, "%g") +
      "% (what no refinement shows: the float sums and the environment's model, at the resolution of an independent "
      "check); a sphere whose RMS bound exceeds the bound goal is integrated again at twice the refinement (at most "
      "twice); the reference is " +
      sums.method;
  for (size_t i = 0; i < pixels.size(); ++i) {
    const SpherePixel& p = pixels[i];
    const Rgb r = lobes_radiance(brdf, res.spheres[size_t(p.sphere)].material, p.n_dot_v, task.pixels, sums.values,
                                 w.task_of[i], w.coat_task_of[i], w.sheen_task_of[i], w.film_task_of[i]);
    ref[index[i]] = r;
    put(res.reference, p.x, p.y, r);
  }
  for (const SpherePixel& p : pixels) bound[size_t(p.sphere)].clear();
  for (size_t k = 0; k < w.bound_index.size(); ++k) {
    const SpherePixel& p = pixels[w.bound_index[k]];
    const Rgb fine =
        lobes_radiance(brdf, res.spheres[size_t(p.sphere)].material, p.n_dot_v, task.bound_pixels, sums.bound_values,
                       w.bound_task_of[k], w.bound_coat_task_of[k], w.bound_sheen_task_of[k], w.bound_film_task_of[k]);
    const Rgb coarse = ref[index[w.bound_index[k]]];
    const double a[3] = {coarse.r, coarse.g, coarse.b}, b[3] = {fine.r, fine.g, fine.b};
    // never 0: the reference is a float sum (its rounding, about 1e-6 relative, is the floor)
    bound[size_t(p.sphere)].push_back(std::max(relative(a, b), kFloatSumFloor));
  }
}

// The reference render, its bound and the error per sphere. A sphere whose RMS bound exceeds
// spec.bound_goal is integrated again at twice the refinement, at most kMaxRefinements times (within
// the refinement's range): a large sphere of a sharp lobe under a sun can need it where the default
// grid's small spheres do not.
constexpr int kMaxRefinements = 2;
void render_reference(Backend& backend, const EnvImage& equirect, const Layout& layout,
                      const std::vector<SpherePixel>& pixels, const TargetBrdf& brdf, const Vec3& v,
                      const PreviewProgress& progress, PreviewResult& res) {
  fill_background(equirect, layout, res);
  std::vector<Rgb> ref(pixels.size());
  std::vector<std::vector<double>> bound(res.spheres.size());
  std::vector<double> refinement_of(res.spheres.size(), res.spec.refinement);
  std::vector<bool> again(res.spheres.size(), true);
  double refinement = res.spec.refinement;
  for (int round = 0;; ++round) {
    std::vector<SpherePixel> subset;
    std::vector<size_t> index;
    for (size_t i = 0; i < pixels.size(); ++i)
      if (again[size_t(pixels[i].sphere)]) {
        subset.push_back(pixels[i]);
        index.push_back(i);
      }
    const double lo = round == 0 ? 0.15 : 0.95, span = round == 0 ? 0.8 : 0.05;
    reference_pass(
        backend, equirect, subset, index, brdf, v, refinement,
        [&](double f) {
          if (progress) progress(lo + span * f, round == 0 ? "reference render" : "reference, refined");
        },
        res, ref, bound);
    for (size_t s = 0; s < res.spheres.size(); ++s)
      if (again[s]) refinement_of[s] = refinement;
    if (round == kMaxRefinements || res.spec.bound_goal <= 0.0 || 2.0 * refinement > kPreviewMaxRefinement) break;
    bool any = false;
    for (size_t s = 0; s < res.spheres.size(); ++s) {
      again[s] = again[s] && reference_bound(bound[s]).rms > res.spec.bound_goal;
      any = any || again[s];
    }
    if (!any) break;
    refinement *= 2.0;
  }
  res.stats = sphere_errors(layout, pixels, res.splitsum, res.reference, res.exposure);
  for (size_t s = 0; s < res.spheres.size(); ++s) {
    PreviewSphereStats& st = res.stats[s];
    const ReferenceBound b = reference_bound(bound[s]);
    st.reference_rms_bound = b.rms;
    st.reference_max_bound = b.max;
    st.bound_pixels = int(bound[s].size());
    st.refinement = refinement_of[s];
  }
}

}  // namespace

// The shares per sphere (PreviewSphereStats::engine_share, bake_share: |ideal - reference| and
// |split-sum - ideal| over |reference|, per pixel) and per group.
void add_shares(const Layout& layout, const std::vector<SpherePixel>& pixels, PreviewResult& res) {
  std::vector<std::vector<double>> engine(res.spheres.size()), bake(res.spheres.size());
  for (const SpherePixel& p : pixels) {
    const size_t at = 3 * (size_t(p.y) * size_t(layout.width) + size_t(p.x));
    const float* s = &res.splitsum.rgb[at];
    const float* i = &res.ideal.rgb[at];
    const float* r = &res.reference.rgb[at];
    const double n = rgb_norm(r);
    const auto rel = [n](double d) { return n > 0.0 ? d / n : (d > 0.0 ? 1.0 : 0.0); };
    engine[size_t(p.sphere)].push_back(rel(rgb_distance(i, r)));
    bake[size_t(p.sphere)].push_back(rel(rgb_distance(s, i)));
  }
  for (size_t k = 0; k < res.spheres.size(); ++k) {
    res.stats[k].engine_share = error_stats(engine[k]);
    res.stats[k].bake_share = error_stats(bake[k]);
  }
  res.share_groups = share_groups(res);
}

}  // namespace detail::preview

PreviewResult render_preview(Backend& backend, const EnvImage& environment, const PreviewSpec& spec,
                             const PreviewProgress& progress, const std::string& scratch_dir) {
  using namespace detail::preview;
  const auto t_start = Clock::now();
  PreviewResult res;
  res.spec = resolve_spec(spec);
  const Layout layout = make_layout(res.spec);
  res.spheres = layout.spheres;
  res.camera = layout.camera;
  res.device = backend.name();
  const std::vector<SpherePixel> pixels = sphere_pixels(layout);

  // The bake: the folder given, or baked first.
  std::unique_ptr<TempFolder> temp;
  std::string folder = res.spec.bake;
  if (folder.empty()) {
    const auto t0 = Clock::now();
    if (res.spec.keep_bake.empty()) {
      temp = std::make_unique<TempFolder>(scratch_dir);
      folder = temp->path();
    } else {
      folder = res.spec.keep_bake;  // kept: the JSON names its files where the user finds them
    }
    bake_first(backend, environment, res.spec.target, folder,
               std::any_of(res.spheres.begin(), res.spheres.end(),
                           [](const PreviewSphere& s) { return preview_has_sheen(s.material); }),
               progress);
    res.times.bake = since(t0);
  }
  auto t0 = Clock::now();
  SplitSumOptions split_options;
  split_options.babylon_mix_ibl_radiance_with_irradiance = res.spec.mix_ibl_radiance_with_irradiance;
  const bool baked_first = res.spec.bake.empty();
  SplitSum split(read_bake_files(folder, res.spec.target, baked_first ? std::string() : environment.source),
                 split_options);
  res.times.read = since(t0);
  if (split.files().diffuse == DiffuseSource::None)
    for (const PreviewSphere& s : res.spheres) {
      const Rgb cd = preview_diffuse_color(s.material);
      if (std::max({cd.r, cd.g, cd.b}) > 0.0)
        throw Error("'" + folder + "': the bake holds no irradiance table (its scene has no diffuse lobe), and '" +
                    s.material.name + "' has one: preview it with a bake that has one (a scene with it, or none)");
    }
  res.bake = split.files().settings;
  if (baked_first && !temp)
    res.bake[0].second = "baked first into " + folder + " (brdfbake bake --target " +
                         std::string(engine_target_name(res.spec.target)) + "), kept";
  if (temp) {
    res.bake[0].second =
        "baked first (brdfbake bake --target " + std::string(engine_target_name(res.spec.target)) + ")";
    // the files by their names alone: the scratch folder is gone with the render (and on a server it
    // is the server's own path)
    const std::string prefix = folder + "/";
    for (auto& [key, value] : res.bake)
      if (value.rfind(prefix, 0) == 0) value = value.substr(prefix.size());
  }
  res.shading = split.steps();
  if (temp)  // the steps name files too: without the scratch folder, gone with the render
    for (auto& [key, value] : res.shading)
      for (size_t at = value.find(folder + "/"); at != std::string::npos; at = value.find(folder + "/", at))
        value.erase(at, folder.size() + 1);
  // KHR_materials_sheen: what this target's split-sum render does with it, in each sheened sphere's notes
  bool sheened = false;
  for (PreviewSphere& sp : res.spheres)
    if (preview_has_sheen(sp.material)) {
      sp.material.notes.push_back(split.sheen_note());
      sheened = true;
    }
  if (sheened && split.renders_sheen()) res.shading.push_back({"sheen", split.sheen_note()});
  // KHR_materials_iridescence: likewise (every iridescent sphere's notes say what its target did)
  bool iridescent = false;
  for (PreviewSphere& sp : res.spheres)
    if (preview_has_iridescence(sp.material)) {
      sp.material.notes.push_back(iridescence_note(res.spec.target));
      iridescent = true;
    }
  if (iridescent && split_sum_renders_iridescence(res.spec.target))
    res.shading.push_back({"iridescence", iridescence_note(res.spec.target)});
  const TargetBrdf brdf = target_brdf(res.spec.target, split.files().dfg_multiscatter);
  res.brdf = brdf.text;
  if (std::any_of(res.spheres.begin(), res.spheres.end(),
                  [](const PreviewSphere& s) { return preview_has_specular_extension(s.material); }))
    res.brdf +=
        "; with KHR_materials_ior / KHR_materials_specular: F0 = mix(specular min(((ior - 1) / (ior + 1))^2 "
        "specularColor, 1), baseColor, metallic), F90 = mix(specular, 1, metallic), F = F0 + (F90 - F0) Fc";
  if (std::any_of(res.spheres.begin(), res.spheres.end(),
                  [](const PreviewSphere& s) { return s.material.clearcoat > 0.0; }))
    res.brdf +=
        "; with KHR_materials_clearcoat: (1 - clearcoat Fcoat(n.v)) f + clearcoat Fcoat(n.v) D_coat V_coat, "
        "Fcoat = 0.04 + 0.96 (1 - n.v)^5, alpha_coat = clearcoatRoughness^2, the geometric normal";
  if (std::any_of(res.spheres.begin(), res.spheres.end(),
                  [](const PreviewSphere& s) { return preview_has_sheen(s.material); }))
    res.brdf +=
        "; with KHR_materials_sheen (under the coat): (1 - max(sheenColor) E(n.v)) f + sheenColor D_Charlie V_sheen, "
        "V_sheen Estevez & Kulla's (the charlie DFG table's default), alpha_sheen = max(sheenRoughness^2, 1e-7), "
        "E the sheen lobe's directional albedo (the charlie table's quadrature)";
  if (std::any_of(res.spheres.begin(), res.spheres.end(),
                  [](const PreviewSphere& s) { return preview_has_iridescence(s.material); }))
    res.brdf +=
        "; with KHR_materials_iridescence: the specular Fresnel mix(F, F_irid(v.h), iridescence), F_irid the thin "
        "film (Belcour & Barla 2017 as the extension writes it; outside index 1, iridescenceIor, the thickness "
        "iridescenceThicknessMaximum) over the dielectric's F0 (weight (1 - metallic) specular) and over baseColor "
        "(weight metallic), integrated per channel; the compensation and the diffuse weight keep F0";
  res.multiscatter = brdf.compensation || brdf.diffuse == DiffuseWeight::FdezAguera;

  const EnvImage equirect = reference_equirect(environment);
  res.environment_median = median_luminance(equirect);
  res.environment_model =
      "each pixel of the " + std::to_string(equirect.width) + "x" + std::to_string(equirect.height) +
      " equirect constant over its cell of longitude x latitude (docs/CONVENTIONS.md's mapping)" +
      (environment.layout == EnvImage::Layout::Cube ? "; the cube input resampled to it (nearest texel)" : "");

  // The split-sum render.
  t0 = Clock::now();
  const Vec3 v = view_vector(layout.camera);
  render_split_sum(layout, pixels, split, v, res, res.splitsum);
  res.times.splitsum = since(t0);
  res.exposure = sheet_exposure(res, pixels, layout.width);
  if (progress) progress(0.15, "split-sum render");

  // The ideal bake and its split-sum render (the error's shares): the same code, its inputs replaced.
  // Not on the scalar reference backend: its chain's levels would take minutes there.
  if (res.spec.reference && res.spec.shares && backend.is_reference())
    res.ideal_bake.push_back({"not_computed", "the scalar reference backend (the ideal bake's chain needs a device)"});
  if (res.spec.reference && res.spec.shares && !backend.is_reference()) {
    if (progress) progress(0.15, "ideal bake");
    t0 = Clock::now();
    IdealBake ideal = ideal_bake(backend, environment, split.files());
    res.ideal_bake = std::move(ideal.settings);
    const SplitSum ideal_split(std::move(ideal.files), split_options);
    render_split_sum(layout, pixels, ideal_split, v, res, res.ideal);
    res.times.ideal = since(t0);
  }

  if (res.spec.reference) render_reference(backend, equirect, layout, pixels, brdf, v, progress, res);
  if (!res.ideal.rgb.empty()) add_shares(layout, pixels, res);
  res.device = backend.name();  // opened by now where the device was used
  res.times.total = since(t_start);
  return res;
}

}  // namespace brdfbake
