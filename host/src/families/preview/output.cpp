// The preview's files (output.hpp).
#include "families/preview/output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "brdfbake/error_figures.hpp"
#include "brdfbake/version.hpp"
#include "families/preview/model.hpp"
#include "io/atomic_file.hpp"
#include "io/image_file.hpp"
#include "io/png_image.hpp"
#include "view/canvas.hpp"

namespace brdfbake::detail::preview {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using view::Canvas;
using view::Rgb8;

constexpr int kMargin = 12;
constexpr int kGap = 16;
constexpr int kLine = 12;
// The error panel's colour scale: log10 of the relative error, 0.1% .. 100%.
constexpr double kErrorLo = 1e-3, kErrorHi = 1.0;

std::string percent(double v) {
  char b[32];
  if (v >= 0.0995)
    std::snprintf(b, sizeof b, "%.0f%%", 100.0 * v);
  else if (v >= 0.00995)
    std::snprintf(b, sizeof b, "%.1f%%", 100.0 * v);
  else
    std::snprintf(b, sizeof b, "%.2f%%", 100.0 * v);
  return b;
}

std::string fmt(double v, const char* f = "%.3g") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

Rgb8 error_colour(double e) {
  if (std::isnan(e)) return view::kBackground;
  const double t =
      (std::log10(std::max(e, kErrorLo)) - std::log10(kErrorLo)) / (std::log10(kErrorHi) - std::log10(kErrorLo));
  return view::cubehelix(std::clamp(t, 0.0, 1.0));
}

// A material's row name: the sphere's name without its roughness suffix (the default grid's).
std::string row_name(const PreviewSphere& s) {
  const std::string& n = s.material.name;
  const size_t at = n.rfind(" r");
  return at != std::string::npos && at > 0 ? n.substr(0, at) : n;
}

// A name on the sheet, shortened to `chars` with "..." (a glTF material's name can be long; the JSON and
// the sheet's regions keep it whole).
constexpr size_t kLabelChars = 28;
std::string shortened(const std::string& n, size_t chars) {
  return n.size() <= chars ? n : n.substr(0, chars - 3) + "...";
}

json vec(const Vec3& v) { return json::array({v.x, v.y, v.z}); }
json rgb(const Rgb& c) { return json::array({c.r, c.g, c.b}); }
json stats(const PreviewErrorStats& s) { return {{"rms", s.rms}, {"p99", s.p99}, {"max", s.max}}; }

}  // namespace

std::string sibling(const std::string& sheet_path, const std::string& suffix) {
  const fs::path p(sheet_path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}

std::vector<float> error_image(const PreviewResult& r) {
  std::vector<float> e(size_t(r.splitsum.width) * size_t(r.splitsum.height), std::numeric_limits<float>::quiet_NaN());
  if (r.reference.rgb.empty()) return e;
  const Layout layout = make_layout(r.spec);
  for (const SpherePixel& p : sphere_pixels(layout)) {
    const size_t i = size_t(p.y) * size_t(r.splitsum.width) + size_t(p.x);
    const float* s = &r.splitsum.rgb[3 * i];
    const float* f = &r.reference.rgb[3 * i];
    double d2 = 0, n2 = 0;
    for (int c = 0; c < 3; ++c) {
      d2 += (double(s[c]) - double(f[c])) * (double(s[c]) - double(f[c]));
      n2 += double(f[c]) * double(f[c]);
    }
    e[i] = float(n2 > 0 ? std::sqrt(d2 / n2) : (d2 > 0 ? 1.0 : 0.0));
  }
  return e;
}

namespace {

// Where the sheet's parts go: the panels' size, their top, the first panel's left edge, and the row
// labels left of it.
struct SheetLayout {
  int w = 0, h = 0;
  bool with_ref = false;
  int panels = 1;
  int top = 0, panel_top = 0, x0 = 0;
  // Rows are named where each row's spheres share a name but for their roughness (the default grid, a
  // material file's roughness series): the name left of the row, as wide as the longest (at least
  // 84 px). Otherwise (a scene's materials) each sphere's name goes under it in the first panel.
  bool named_rows = true;
  std::vector<std::string> rows;
  // The numbers under the spheres of the error panel (numbers_fit), and the pixels the bottom row's
  // take below the panels.
  bool numbers = false;
  int below = 0;
};

// The numbers under each sphere of the error panel (2 lines, 3 with the shares) fit between the
// sphere and the one below it, and across its cell: at the default 512^2 they do; at 384 x 192 (cells
// 32 pixels high, spheres 29) they covered the next row. Else they are left out, and the header says
// the height that holds them. `min_height`: that height.
bool numbers_fit(const PreviewResult& r, int* min_height) {
  int rows = 0, columns = 0;
  double radius = 0.0;
  for (const PreviewSphere& sp : r.spheres) {
    rows = std::max(rows, sp.row + 1);
    columns = std::max(columns, sp.column + 1);
    radius = std::max(radius, sp.radius);
  }
  if (rows == 0) return false;
  const int lines = r.ideal.rgb.empty() ? 2 : 3;
  const double need = 2.0 * radius + 2.0 + lines * (kLine - 2);
  const double cell_h = double(r.splitsum.height) / rows, cell_w = double(r.splitsum.width) / columns;
  // a sphere is 0.92 of the smaller side of its cell (make_layout): cells taller than wide keep its
  // width's sphere and hold the lines under it
  *min_height = int(std::ceil(rows * (0.92 * cell_w + 2.0 + lines * (kLine - 2))));
  return need <= cell_h && view::text_width("b100.0%") + 2 <= cell_w;
}

SheetLayout sheet_layout(const PreviewResult& r) {
  SheetLayout l;
  l.w = r.splitsum.width;
  l.h = r.splitsum.height;
  l.with_ref = !r.reference.rgb.empty();
  l.panels = l.with_ref ? 3 : 1;
  l.rows.resize(r.spheres.size());
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    l.rows[s] = row_name(r.spheres[s]);
    for (size_t o = 0; o < s; ++o)
      l.named_rows = l.named_rows && (r.spheres[o].row != r.spheres[s].row || l.rows[o] == l.rows[s]);
  }
  int label_w = l.named_rows ? 84 : 0;
  if (l.named_rows)
    for (std::string& row : l.rows) {
      row = shortened(row, kLabelChars);
      label_w = std::max(label_w, view::text_width(row) + kGap);
    }
  // title, five lines of text (six with the error's shares)
  l.top = kMargin + 2 * kLine + (r.ideal.rgb.empty() ? 5 : 6) * kLine + kGap;
  l.panel_top = l.top + 2 * kLine + 4;  // the panel's title, the columns' roughness
  l.x0 = kMargin + label_w;
  int min_height = 0;
  l.numbers = l.with_ref && numbers_fit(r, &min_height);
  if (l.numbers) {
    const int lines = r.ideal.rgb.empty() ? 2 : 3;
    for (const PreviewSphere& sp : r.spheres)
      l.below = std::max(l.below, int(sp.centre_y + sp.radius) + 2 + lines * (kLine - 2) - l.h);
  }
  return l;
}

// The title and the five lines of text under it (the last: what the target's emulation was held to); the
// sheet's tone-map and colour-scale texts.
void sheet_header(const PreviewResult& r, const std::string& title, const SheetLayout& l, Canvas& c,
                  ContactSheet& sheet) {
  char ev[64];
  std::snprintf(ev, sizeof ev, "%+.2f", r.exposure);
  sheet.tone_map_text = std::string("HDR: exposure ") + ev + " EV (0.18 / the environment's median luminance " +
                        fmt(r.environment_median) +
                        ", at most 0.8 / the spheres'), ACES filmic fit (Narkowicz 2015), sRGB";
  sheet.colour_scale_text =
      "error: |split-sum - reference| / |reference| per pixel, cubehelix (Green 2011) over log10, " +
      percent(kErrorLo) + " (black) to " + percent(kErrorHi) + " (white)";
  int y = kMargin;
  c.text(kMargin, y, title, view::kText, 2);
  y += 2 * kLine + 2;
  c.text(kMargin, y,
         "brdfbake " + std::string(kVersion) + ", target " + engine_target_name(r.spec.target) + ", device " + r.device,
         view::kDim);
  c.text(kMargin, y + kLine, sheet.tone_map_text, view::kText);
  if (l.with_ref) c.text(kMargin, y + 2 * kLine, sheet.colour_scale_text, view::kText);
  double worst_bound = 0.0;
  for (const auto& s : r.stats) worst_bound = std::max(worst_bound, s.reference_rms_bound);
  int min_height = 0;
  if (l.with_ref && numbers_fit(r, &min_height))
    c.text(
        kMargin, y + 3 * kLine,
        "under each sphere: relative RMS error in linear radiance, then the 99th percentile in 8-bit sRGB steps; the "
        "reference is within " +
            percent(worst_bound) + " RMS on every sphere",
        view::kDim);
  else if (l.with_ref)
    c.text(kMargin, y + 3 * kLine,
           "the cells are too small for the numbers under each sphere (the JSON has them; --height " +
               std::to_string(min_height) + " holds them); the reference is within " + percent(worst_bound) +
               " RMS on every sphere",
           view::kDim);
  else
    c.text(kMargin, y + 3 * kLine, "the split-sum render alone (no reference: --no-reference)", view::kDim);
  c.text(kMargin, y + 4 * kLine, "emulation held to: " + engine_settings(r.spec.target).held_to_short, view::kDim);
  if (!r.ideal.rgb.empty()) {
    // the error's shares per group: the engine's (its split sum from an ideal bake) and the bake's
    std::string line = std::string("error's shares, median over a group's spheres (engine | bake") +
                       (numbers_fit(r, &min_height) ? ", the third line under each sphere the bake's):" : "):");
    const size_t shown = std::min<size_t>(r.share_groups.size(), 8);
    for (size_t g = 0; g < shown; ++g)
      line += (g ? ", " : " ") + shortened(r.share_groups[g].name, 12) + " " +
              percent(r.share_groups[g].engine_median) + " | " + percent(r.share_groups[g].bake_median);
    if (shown < r.share_groups.size()) line += ", ... (NAME.json: every group)";
    c.text(kMargin, y + 5 * kLine, line, view::kText);
  }
}

// Panel k (0 split-sum, 1 reference, 2 error): its title, the columns' roughness where a column's
// spheres share one (the default grid), its pixels, and its region.
void sheet_panel(const PreviewResult& r, const SheetLayout& l, int k, const std::vector<float>& err, Canvas& c,
                 ContactSheet& sheet) {
  ViewOptions vo;
  vo.exposure = r.exposure;
  const int px = l.x0 + k * (l.w + kGap);
  const std::string name = k == 0   ? "split-sum: " + std::string(engine_target_name(r.spec.target))
                           : k == 1 ? "reference (converged integral)"
                                    : "relative error";
  c.text(px, l.top, name, view::kText);
  for (const PreviewSphere& sp : r.spheres) {
    if (sp.row != 0) continue;
    bool shared = true;
    for (const PreviewSphere& o : r.spheres)
      shared = shared && (o.column != sp.column || o.material.roughness == sp.material.roughness);
    if (!shared) continue;
    const std::string label = "r " + fmt(sp.material.roughness, "%.2g");
    c.text(px + int(sp.centre_x) - view::text_width(label) / 2, l.top + kLine, label, view::kDim);
  }
  SheetRegion region;
  region.role = k == 0 ? "split-sum" : k == 1 ? "reference" : "error";
  region.label = name;
  region.x = px;
  region.y = l.panel_top;
  region.width = l.w;
  region.height = l.h;
  if (k == 2) {
    region.lo = kErrorLo;
    region.hi = kErrorHi;
    region.log_scale = true;
  }
  sheet.regions.push_back(region);
  for (int j = 0; j < l.h; ++j)
    for (int i = 0; i < l.w; ++i) {
      const size_t at = size_t(j) * size_t(l.w) + size_t(i);
      Rgb8 colour;
      if (k == 2)
        colour = std::isnan(err[at]) ? Rgb8{16, 16, 16} : error_colour(err[at]);
      else
        colour = view::tone_map(&(k == 0 ? r.splitsum : r.reference).rgb[3 * at], vo);
      c.set(px + i, l.panel_top + j, colour);
    }
}

// The row labels (or each sphere's name), each sphere's region, and the numbers under each sphere in
// the error panel.
void sheet_sphere_labels(const PreviewResult& r, const SheetLayout& l, Canvas& c, ContactSheet& sheet) {
  std::string last_row;
  const bool fit = l.numbers;
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    const PreviewSphere& sp = r.spheres[s];
    if (l.named_rows && sp.column == 0 && l.rows[s] != last_row) {
      c.text(kMargin, l.panel_top + int(sp.centre_y) - kLine / 2, l.rows[s], view::kText);
      last_row = l.rows[s];
    }
    if (!l.named_rows) {  // the sphere's name under it, as many characters as its cell holds
      const size_t chars = size_t(std::max(4.0, (2.0 * sp.radius + kGap) / view::text_width("m")));
      const std::string name = shortened(sp.material.name, chars);
      const int ty = l.panel_top + std::min(int(sp.centre_y + sp.radius) + 2, l.h - kLine);
      c.text(l.x0 + int(sp.centre_x) - view::text_width(name) / 2, ty, name, view::kText);
    }
    SheetRegion region;
    region.role = "sphere";
    region.label = sp.material.name;
    region.x = l.x0 + int(sp.centre_x - sp.radius);
    region.y = l.panel_top + int(sp.centre_y - sp.radius);
    region.width = region.height = int(2 * sp.radius);
    sheet.regions.push_back(region);
    if (!l.with_ref || s >= r.stats.size() || !fit) continue;
    const std::string a = percent(r.stats[s].linear.rms), b = fmt(r.stats[s].srgb8.p99, "%.0f");
    const int below = int(sp.centre_y + sp.radius) + 2;
    const int px = l.x0 + 2 * (l.w + kGap);
    const int ty = l.panel_top + below;  // the bottom row's below the panel (l.below)
    c.text(px + int(sp.centre_x) - view::text_width(a) / 2, ty, a, view::kText);
    c.text(px + int(sp.centre_x) - view::text_width(b) / 2, ty + kLine - 2, b, view::kDim);
    if (!r.ideal.rgb.empty()) {
      const std::string bake = "b" + percent(r.stats[s].bake_share.rms);
      c.text(px + int(sp.centre_x) - view::text_width(bake) / 2, ty + 2 * kLine - 4, bake, view::kDim);
    }
  }
}

// The error panel's colour scale under it.
void sheet_error_scale(const SheetLayout& l, Canvas& c, ContactSheet& sheet) {
  const int px = l.x0 + 2 * (l.w + kGap), sy = l.panel_top + l.h + l.below + kGap;
  for (int i = 0; i < l.w; ++i) {
    const double t = double(i) / (l.w - 1);
    const Rgb8 col = view::cubehelix(t);
    c.fill_rect(px + i, sy, 1, 8, col);
  }
  c.text(px, sy + 10, percent(kErrorLo), view::kText);
  c.text(px + l.w / 3 - 12, sy + 10, "1%", view::kText);
  c.text(px + 2 * l.w / 3 - 12, sy + 10, "10%", view::kText);
  c.text(px + l.w - view::text_width(percent(kErrorHi)), sy + 10, percent(kErrorHi), view::kText);
  SheetRegion region;
  region.role = "colour scale";
  region.label = "relative error";
  region.x = px;
  region.y = sy;
  region.width = l.w;
  region.height = 8;
  region.lo = kErrorLo;
  region.hi = kErrorHi;
  region.log_scale = true;
  sheet.regions.push_back(region);
}

}  // namespace

ContactSheet preview_sheet(const PreviewResult& r, const std::string& title) {
  const SheetLayout l = sheet_layout(r);
  const int sheet_w = std::max(l.x0 + kMargin + l.panels * l.w + (l.panels - 1) * kGap, 640);
  const int sheet_h = l.panel_top + l.h + l.below + kGap + 3 * kLine + kMargin;
  Canvas c(sheet_w, sheet_h, view::kBackground);
  ContactSheet sheet;
  sheet_header(r, title, l, c, sheet);
  const std::vector<float> err = error_image(r);
  for (int k = 0; k < l.panels; ++k) sheet_panel(r, l, k, err, c, sheet);
  sheet_sphere_labels(r, l, c, sheet);
  if (l.with_ref) sheet_error_scale(l, c, sheet);
  sheet.width = c.width();
  sheet.height = c.height();
  sheet.rgb = std::move(c.rgb());
  return sheet;
}

namespace {

// The camera of the JSON, with how to recompute any pixel's normal.
json camera_json(const PreviewCamera& cam) {
  return {{"projection", "orthographic"},
          {"view_direction", vec(cam.view_direction)},
          {"up", vec(cam.up)},
          {"right", vec(cam.right)},
          {"yaw", cam.yaw},
          {"pitch", cam.pitch},
          {"frame", "the environment's (docs/CONVENTIONS.md: +Y up, the equirect's centre looking down +Z)"},
          {"normal",
           "for a pixel centre (x, y) on a sphere, d = ((x - centre_x), (y - centre_y)) / radius, "
           "n = d.x right - d.y up + sqrt(1 - |d|^2) (-view_direction); v = -view_direction"},
          {"background_fov", cam.background_fov},
          {"background",
           "the split-sum image shows level 0 of the bake's chain (the engine's skybox), the reference "
           "the environment's cells, through a pinhole of background_fov degrees (vertical)"}};
}

// A sphere of the JSON: its place, material, notes and (with its stats) its errors and bound.
json sphere_json(const PreviewSphere& sp, const PreviewSphereStats* stats_of, bool shares) {
  json o;
  o["name"] = sp.material.name;
  o["row"] = sp.row;
  o["column"] = sp.column;
  o["centre"] = json::array({sp.centre_x, sp.centre_y});
  o["radius"] = sp.radius;
  o["material"] = {
      {"baseColor", rgb(sp.material.base_color)}, {"metallic", sp.material.metallic},
      {"roughness", sp.material.roughness},       {"alpha", sp.material.roughness * sp.material.roughness},
      {"F0", rgb(preview_f0(sp.material))},       {"diffuse_color", rgb(preview_diffuse_color(sp.material))}};
  if (preview_has_specular_extension(sp.material)) {
    o["material"]["ior"] = sp.material.ior;
    o["material"]["specular"] = sp.material.specular;
    o["material"]["specular_color"] = rgb(sp.material.specular_color);
    o["material"]["F90"] = preview_f90(sp.material);
  }
  if (sp.material.clearcoat > 0.0) {
    o["material"]["clearcoat"] = sp.material.clearcoat;
    o["material"]["clearcoat_roughness"] = sp.material.clearcoat_roughness;
  }
  if (preview_has_sheen(sp.material)) {
    o["material"]["sheen_color"] = rgb(sp.material.sheen_color);
    o["material"]["sheen_roughness"] = sp.material.sheen_roughness;
  }
  if (preview_has_iridescence(sp.material)) {
    o["material"]["iridescence"] = sp.material.iridescence;
    o["material"]["iridescence_ior"] = sp.material.iridescence_ior;
    o["material"]["iridescence_thickness"] = sp.material.iridescence_thickness;
  }
  if (!sp.material.notes.empty()) o["notes"] = sp.material.notes;
  if (stats_of) {
    const PreviewSphereStats& st = *stats_of;
    o["pixels"] = st.pixels;
    o["error"] = {{"linear", stats(st.linear)}, {"srgb8", stats(st.srgb8)}};
    o["reference_bound"] = {{"rms", st.reference_rms_bound},
                            {"max", st.reference_max_bound},
                            {"pixels", st.bound_pixels},
                            {"refinement", st.refinement}};
    if (shares) {
      o["engine_share"] = stats(st.engine_share);
      o["bake_share"] = stats(st.bake_share);
    }
  }
  return o;
}

}  // namespace

std::string preview_json(const PreviewResult& r, const std::string& environment, const std::string& sheet_path) {
  json j;
  j["generator"] = std::string("brdfbake ") + kVersion;
  j["kind"] = "preview";
  j["target"] = engine_target_name(r.spec.target);
  j["files"] = {
      {"sheet", fs::path(sheet_path).filename().string()},
      {"splitsum", fs::path(sibling(sheet_path, "_splitsum.exr")).filename().string()},
      {"reference",
       r.reference.rgb.empty() ? json() : json(fs::path(sibling(sheet_path, "_reference.exr")).filename().string())}};
  j["environment"] = {{"source", environment},
                      {"model", r.environment_model},
                      {"median_luminance", r.environment_median},
                      {"exposure_ev", r.exposure}};
  j["image"] = {
      {"width", r.splitsum.width},
      {"height", r.splitsum.height},
      {"pixel",
       "pixel (i, j) covers [i, i + 1) x [j, j + 1), row 0 at the top; shaded at its centre (i + 0.5, j + 0.5)"},
      {"background", preview_background_name(r.spec.background)}};
  j["camera"] = camera_json(r.camera);
  j["brdf"] = r.brdf;
  j["multiple_scattering_compensation"] = r.multiscatter;
  json spheres = json::array();
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    spheres.push_back(sphere_json(r.spheres[s], s < r.stats.size() ? &r.stats[s] : nullptr, !r.ideal.rgb.empty()));
  }
  j["spheres"] = spheres;
  if (!r.stats.empty()) {
    double worst_rms = 0, worst_max = 0;
    for (const auto& st : r.stats) {
      worst_rms = std::max(worst_rms, st.reference_rms_bound);
      worst_max = std::max(worst_max, st.reference_max_bound);
    }
    j["reference"] = {{"definition",
                       "per pixel, the integral of the BRDF above against the environment's model, no split "
                       "sum, no prefiltering, no storage"},
                      {"refinement", r.spec.refinement},
                      {"bound_goal", r.spec.bound_goal},
                      {"bound_definition", r.bound_definition},
                      {"bound_rms", worst_rms},
                      {"bound_max", worst_max}};
    // the preview's error figure as the manifest names it (brdfbake/error_figures.hpp)
    const ErrorFigure& figure = error_figure(TableKind::Preview);
    j["error_name"] = figure.name;
    j[figure.name] = worst_rms;
    j["error_definition"] = {
        {"linear",
         "per pixel |split-sum - reference| / |reference| (Euclidean norms of the linear RGB triples); per sphere "
         "the RMS, the 99th percentile and the max over its pixels"},
        {"srgb8",
         "per pixel the largest difference of the three 8-bit sRGB channels after the sheet's exposure and tone map"}};
  }
  if (!r.ideal.rgb.empty() && !r.stats.empty()) {
    json groups = json::array();
    for (const PreviewShareGroup& g : r.share_groups)
      groups.push_back({{"name", g.name},
                        {"spheres", g.spheres},
                        {"error", {{"median", g.error_median}, {"worst", g.error_worst}}},
                        {"engine_share", {{"median", g.engine_median}, {"worst", g.engine_worst}}},
                        {"bake_share", {{"median", g.bake_median}, {"worst", g.bake_worst}}}});
    json ideal = json::object();
    for (const auto& [k, v] : r.ideal_bake) ideal[k] = v;
    j["shares"] = {
        {"definition",
         "engine_share: per pixel |ideal - reference| / |reference|, the target's split-sum approximation itself (its "
         "shader rendered from the ideal bake: what no file can change); bake_share: per pixel |split-sum - ideal| / "
         "|reference|, what the files add (resolution, convergence, storage); per sphere the RMS, the 99th "
         "percentile and the max over its pixels, per group the median and the worst sphere's RMS"},
        {"how_they_add",
         "the difference images add exactly, split-sum - reference = (split-sum - ideal) + (ideal - reference), pixel "
         "by pixel; their RMS norms do not: |engine - bake| <= error <= engine + bake per sphere"},
        {"ideal_bake", ideal},
        {"groups", groups}};
  }
  json bake = json::object();
  for (const auto& [k, v] : r.bake) bake[k] = v;
  j["bake"] = bake;
  json shading = json::object();
  for (const auto& [k, v] : r.shading) shading[k] = v;
  j["split_sum"] = shading;
  j["split_sum_held_to"] = engine_settings(r.spec.target).held_to;
  j["times"] = {{"bake", r.times.bake},
                {"read", r.times.read},
                {"splitsum", r.times.splitsum},
                {"reference", r.times.reference},
                {"reference_device", r.times.reference_device},
                {"bound", r.times.bound},
                {"ideal", r.times.ideal},
                {"total", r.times.total}};
  j["device"] = r.device;
  return j.dump(2) + "\n";
}

void write_preview(const PreviewResult& r, const std::string& environment, const std::string& sheet_path) {
  const std::string title = "brdfbake preview";
  const std::vector<std::pair<std::string, std::string>> attributes = {
      {"brdfbake:kind", "preview"},
      {"brdfbake:target", engine_target_name(r.spec.target)},
      {"brdfbake:json", fs::path(sibling(sheet_path, ".json")).filename().string()},
      {"brdfbake:pixel", "linear RGB radiance, row 0 at the top"}};
  // The float images (uncompressed: io::ExrCompression::None says why) on a second thread while the
  // sheet is drawn and encoded here. The four files are one output (issue 34, class 1): each is
  // staged beside its name, every name is checked free for a file (no folder, device or FIFO in the
  // way) before the first rename, and the sheet is renamed last; a reference not rendered this time
  // leaves no NAME_reference.exr of an earlier run beside the new sheet.
  const std::string json_path = sibling(sheet_path, ".json"), split_path = sibling(sheet_path, "_splitsum.exr"),
                    ref_path = sibling(sheet_path, "_reference.exr");
  io::TempFile split(split_path);
  std::optional<io::TempFile> ref;
  if (!r.reference.rgb.empty()) ref.emplace(ref_path);
  std::exception_ptr failed;
  std::thread exr([&] {
    try {
      io::write_exr(split, r.splitsum.width, r.splitsum.height, 3, r.splitsum.rgb.data(), attributes,
                    io::ExrCompression::None);
      if (ref)
        io::write_exr(*ref, r.reference.width, r.reference.height, 3, r.reference.rgb.data(), attributes,
                      io::ExrCompression::None);
    } catch (...) {
      failed = std::current_exception();
    }
  });
  try {
    io::TempFile json_file(json_path);
    io::write_bytes(json_file, preview_json(r, environment, sheet_path));
    const ContactSheet sheet = preview_sheet(r, title);
    // zlib level 3: a tenth of level 9's time for a 1600 x 700 sheet, a slightly larger file
    constexpr int kSheetLevel = 3;
    io::TempFile png(sheet_path);
    std::vector<uint8_t> bytes;
    try {
      bytes = io::encode_png_rgb8(
          sheet.width, sheet.height, sheet.rgb,
          {{"Software", std::string("brdfbake ") + kVersion},
           {"Description", "brdfbake preview: " + sheet.tone_map_text + "; " + sheet.colour_scale_text}},
          kSheetLevel);
    } catch (const Error& e) {
      throw Error("cannot write '" + sheet_path + "': " + e.what());
    }
    io::write_bytes(png, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    exr.join();
    if (failed) std::rethrow_exception(failed);
    for (const std::string& path : {json_path, split_path, ref_path, sheet_path}) {
      std::error_code ec;
      if (fs::is_directory(path, ec))
        throw Error("cannot write '" + path + "': a folder of that name is in the way (nothing was written)");
    }
    split.commit();
    if (ref) {
      ref->commit();
    } else {
      std::error_code ec;
      if (fs::is_regular_file(fs::symlink_status(ref_path, ec))) fs::remove(ref_path, ec);
    }
    json_file.commit();
    png.commit();
  } catch (...) {
    if (exr.joinable()) exr.join();
    throw;
  }
}

}  // namespace brdfbake::detail::preview
