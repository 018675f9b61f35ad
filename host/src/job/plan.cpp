// The rules that turn a scene's materials into the tables they call for (docs/SCENES.md states each
// rule, what it bakes and why). Every table of the plan records the rules and the materials that
// asked for it; a table asked for twice (by two materials, or two rules) is listed once.
#include "brdfbake/plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "brdfbake/engines.hpp"
#include "io/json_input.hpp"
#include "job/job_json.hpp"

namespace brdfbake {

namespace {

std::string num(double v, const char* f = "%.6g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

double max3(const Rgb3& c) { return std::max(c[0], std::max(c[1], c[2])); }

// The rule names, in the order they are applied and listed.
constexpr const char* kUnlit = "KHR_materials_unlit";
constexpr const char* kEmissiveOnly = "emissive-only";
constexpr const char* kCore = "metallic-roughness";
constexpr const char* kClearcoat = "KHR_materials_clearcoat";
constexpr const char* kSheen = "KHR_materials_sheen";
constexpr const char* kAnisotropy = "KHR_materials_anisotropy";
constexpr const char* kIor = "KHR_materials_ior";
constexpr const char* kSpecular = "KHR_materials_specular";
constexpr const char* kDispersion = "KHR_materials_dispersion";
constexpr const char* kTransmission = "KHR_materials_transmission";
constexpr const char* kVolume = "KHR_materials_volume";
constexpr const char* kIridescence = "KHR_materials_iridescence";
// Not a material's rule: what an engine target's file set holds whatever the materials.
constexpr const char* kEngineSet = "engine-file-set";
const char* const kRuleOrder[] = {kUnlit, kEmissiveOnly, kCore,       kClearcoat,    kSheen,  kAnisotropy,
                                  kIor,   kSpecular,     kDispersion, kTransmission, kVolume, kIridescence};

class Planner {
 public:
  explicit Planner(const PlanOptions& o) : o_(o) {
    plan_.options = o;
    plan_.job.environment = o.environment;
    plan_.job.device = o.device;
    plan_.job.precision = o.precision;
    plan_.job.source = "bake plan";
    plan_.job.sanitize = o.sanitize;
    plan_.job.target = o.target;
    if (o.sh_window) sh_window_ = *o.sh_window;  // the user's, over the target's (set below unless given)
    if (o.target != "generic") {
      // The engine's conventions, unless the options say otherwise.
      const EngineSettings e = engine_settings(engine_target_from_name(o.target));
      if (!o_.schedule) o_.schedule = roughness_schedule_name(e.schedule);
      if (!o_.chain_size) o_.chain_size = e.size;
      if (!o_.cube_min_size) o_.cube_min_size = e.min_size;
      if (e.sh_window != ShWindow::None && !o.sh_window) sh_window_ = sh_window_name(e.sh_window);
      plan_.job.engine_name = o.engine_name;
      // What the engine's writer would refuse after the bake (engines/engine_writers.cpp, check_chain),
      // refused here, before anything is baked: the command line, its --dry-run and POST /v1/bake alike.
      const int size = *o_.chain_size;
      if (e.power_of_two && (size & (size - 1)) != 0)
        throw Error("chain_size: " + o.target + " needs a power-of-two face size (got " + std::to_string(size) + ")");
      if (*o_.schedule != roughness_schedule_name(e.schedule))
        throw Error("schedule: " + o.target + " reads its levels with the '" + roughness_schedule_name(e.schedule) +
                    "' schedule (" + e.lod_formula + "), not '" + *o_.schedule + "'");
    }
  }

  Plan& plan() { return plan_; }

  // Adds `t` (or finds the identical table already planned) and records who asked for it.
  void ask(TableRequest t, const std::string& rule, const std::string& purpose, const std::string& material) {
    t.precision = o_.precision;
    // ASTC is for the chains; every other table keeps its kind's pixel
    t.pixel = (o_.pixel == "astc4x4" || o_.pixel == "astc6x6") && t.kind != TableKind::Prefilter ? "" : o_.pixel;
    if (o_.clamp_f16 && find_param_def(table_schema(t.kind), "clamp_f16")) t.set("clamp_f16", true);
    const std::string key = key_of(t);
    auto it = index_.find(key);
    size_t at;
    if (it == index_.end()) {
      at = plan_.job.tables.size();
      index_[key] = at;
      plan_.job.tables.push_back(std::move(t));
    } else {
      at = it->second;
    }
    auto& reqs = plan_.job.tables[at].requested_by;
    auto r = std::find_if(reqs.begin(), reqs.end(),
                          [&](const Request& q) { return q.rule == rule && q.purpose == purpose; });
    if (r == reqs.end()) {
      reqs.push_back({rule, purpose, {}, {}});
      r = reqs.end() - 1;
    }
    if (!material.empty() && std::find(r->materials.begin(), r->materials.end(), material) == r->materials.end())
      r->materials.push_back(material);
    fired(rule);
  }

  void fired(const std::string& rule) { fired_.insert(rule); }

  // Sets the note of every request of `rule` (e.g. a roughness range).
  void note_rule(const std::string& rule, const std::string& note) {
    for (auto& t : plan_.job.tables)
      for (auto& r : t.requested_by)
        if (r.rule == rule) r.note = note;
  }

  void finish() {
    // An engine target's file set holds the environment's diffuse light beside its chain whatever
    // the materials (Filament's SH key, the .env's polynomial, the glTF light's required
    // irradianceCoefficients, the Khronos viewer's Lambertian cube): its engine loads the IBL whole.
    // A scene that asks for the chain alone (every material a metal) gets the irradiance for the set.
    bool target_irradiance = false;
    if (plan_.job.target != "generic") {
      const auto& tables = plan_.job.tables;
      const bool has_chain = std::any_of(tables.begin(), tables.end(), [](const TableRequest& t) {
        return t.kind == TableKind::Prefilter && t.find("distribution") && t.text("distribution") == "ggx";
      });
      const bool has_irradiance = std::any_of(tables.begin(), tables.end(),
                                              [](const TableRequest& t) { return t.kind == TableKind::Irradiance; });
      if (has_chain && !has_irradiance) {
        ask(irradiance(), kEngineSet,
            "diffuse irradiance for the " + plan_.job.target +
                " file set, which holds it whatever the materials (its engine loads the IBL whole)",
            "");
        target_irradiance = true;
      }
    }
    for (const char* rule : kRuleOrder)
      if (fired_.count(rule)) plan_.rules_fired.push_back(rule);
    if (target_irradiance) plan_.rules_fired.push_back(kEngineSet);
    // Only what the target's engine loads (issue 34): tables no file of its set holds and its
    // engine never reads are not baked, and the plan says why.
    if (plan_.job.target != "generic") {
      const EngineSettings e = engine_settings(engine_target_from_name(plan_.job.target));
      auto& tables = plan_.job.tables;
      const auto unread = [&](const TableRequest& t) {
        const bool dfg = t.kind == TableKind::Ggx || t.kind == TableKind::GgxMultiscatter;
        const bool charlie =
            t.kind == TableKind::Charlie ||
            (t.kind == TableKind::Prefilter && t.find("distribution") && t.text("distribution") == "charlie");
        return (dfg && !e.reads_dfg_tables) || (charlie && !e.reads_charlie);
      };
      const size_t before = tables.size();
      tables.erase(std::remove_if(tables.begin(), tables.end(), unread), tables.end());
      if (tables.size() != before)
        plan_.job.notes.push_back(
            std::to_string(before - tables.size()) + " table(s) not baked: " + plan_.job.target +
            " never reads them (" + (e.reads_dfg_tables ? "" : "its engine samples its own DFG table") +
            (!e.reads_dfg_tables && !e.reads_charlie ? "; " : "") +
            (e.reads_charlie ? "" : "its sheen is lit by the GGX chain, with no Charlie IBL") + ")");
      index_.clear();
      for (size_t i = 0; i < tables.size(); ++i) index_[key_of(tables[i])] = i;
    }
    validate_job(plan_.job);  // fills defaults, canonical parameter order and output names
  }

  // ---- the tables ----
  TableRequest dfg(TableKind kind, const std::string& visibility = {}) const {
    TableRequest t;
    t.kind = kind;
    if (o_.lut_size) t.params.push_back({"size", double(*o_.lut_size)});
    if (kind == TableKind::Charlie && !visibility.empty()) t.params.push_back({"sheen_visibility", visibility});
    t.format = o_.table_format;
    return t;
  }
  TableRequest specular_dfg() const {
    return dfg(o_.energy_compensation ? TableKind::GgxMultiscatter : TableKind::Ggx);
  }
  TableRequest prefilter(const std::string& distribution) const {
    TableRequest t;
    t.kind = TableKind::Prefilter;
    t.params.push_back({"distribution", distribution});
    if (o_.chain_size) t.params.push_back({"chain_size", double(*o_.chain_size)});
    if (o_.cube_min_size) t.params.push_back({"min_size", double(*o_.cube_min_size)});
    if (o_.schedule) t.params.push_back({"schedule", *o_.schedule});
    if (o_.chain_max_error > 0) t.params.push_back({"chain_max_error", o_.chain_max_error});
    t.format = o_.cube_format;
    return t;
  }
  TableRequest irradiance() const {
    TableRequest t;
    t.kind = TableKind::Irradiance;
    if (o_.sh_order) t.params.push_back({"sh_order", double(*o_.sh_order)});
    if (!sh_window_.empty()) t.params.push_back({"sh_window", sh_window_});
    // The Khronos viewer takes a Lambertian cube beside the SH (docs/ENGINES.md).
    if (o_.target == "khronos-viewer") {
      t.format = "ktx2";
      return t;
    }
    t.format = "json";
    return t;
  }
  TableRequest fresnel(const std::string& model, const std::vector<double>& ior, double ior_outside,
                       bool vs_exact) const {
    TableRequest t;
    t.kind = TableKind::Fresnel;
    t.params.push_back({"model", model});
    if (ior.size() == 1)
      t.params.push_back({"ior", ior[0]});
    else
      t.params.push_back({"ior", ior});
    if (ior_outside != 1.0) t.params.push_back({"ior_outside", ior_outside});
    if (o_.fresnel_size) t.params.push_back({"size", double(*o_.fresnel_size)});
    if (vs_exact) t.params.push_back({"vs_exact", true});
    // The error columns make six channels: CSV (or a C header) holds them, images do not.
    t.format = vs_exact ? (o_.table_format == "h" ? "h" : "csv") : o_.table_format;
    return t;
  }
  TableRequest thin_film(double film_ior, const std::string& base_key, const ParamValue& base, double lo,
                         double hi) const {
    TableRequest t;
    t.kind = TableKind::ThinFilm;
    t.params.push_back({"film_ior", film_ior});
    t.params.push_back({base_key, base});
    t.params.push_back({"thickness_min", lo});
    t.params.push_back({"thickness_max", hi});
    if (o_.thin_film_size) t.params.push_back({"size", double(*o_.thin_film_size)});
    t.format = o_.table_format;
    return t;
  }

 private:
  static std::string key_of(const TableRequest& t) {
    std::string k = table_kind_name(t.kind);
    for (const auto& p : t.params) {
      k += "|" + p.name + "=";
      if (auto b = std::get_if<bool>(&p.value))
        k += *b ? "true" : "false";
      else if (auto d = std::get_if<double>(&p.value))
        k += num(*d, "%.9g");
      else if (auto s = std::get_if<std::string>(&p.value))
        k += *s;
      else
        for (double v : std::get<std::vector<double>>(p.value)) k += num(v, "%.9g") + ",";
    }
    return k;
  }

  PlanOptions o_;
  std::string sh_window_;  // the engine target's, when it has one
  Plan plan_;
  std::map<std::string, size_t> index_;
  std::set<std::string> fired_;
};

// A range of values over the materials a rule fired for.
struct Range {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  void add(double a, double b) {
    lo = std::min(lo, a);
    hi = std::max(hi, b);
  }
  bool empty() const { return lo > hi; }
  std::string text() const { return lo == hi ? num(lo, "%.3g") : num(lo, "%.3g") + " to " + num(hi, "%.3g"); }
};

// IORs are compared and named at 6 significant digits (glTF files store float32: 1.33 is
// 1.3300000429153442), so that the same index in two materials is one table.
double round_ior(double v) { return std::stod(num(v, "%.6g")); }

// The IOR of each colour channel: one value, or three with KHR_materials_dispersion (the
// extension's own implementation note: half the spread F-C on either side of n_d, red lowest,
// clamped at 1).
std::vector<double> channel_iors(const SceneMaterial& m, bool dispersion) {
  const double n = m.ior;
  if (!dispersion) return {round_ior(n)};
  const double half_spread = (n - 1.0) * 0.025 * m.dispersion;
  return {round_ior(std::max(1.0, n - half_spread)), round_ior(n), round_ior(n + half_spread)};
}

std::string ior_text(const std::vector<double>& iors) {
  std::string s;
  for (size_t i = 0; i < iors.size(); ++i) s += (i ? "/" : "") + num(iors[i]);
  return s;
}

bool dispersion_fires(const SceneMaterial& m) {
  return m.dispersion_ext && m.dispersion > 0 && m.transmission > 0 && m.volume_ext && (m.thickness > 0) &&
         m.ior != 1.0 && m.ior != 0.0;
}

// Whether the material emits light and reflects nothing the renderer's IBL would add: a black base
// colour (factor 0: a texture is multiplied by it) and no lobe extension of its own.
bool emissive_only(const SceneMaterial& m) {
  const bool emits = max3(m.emissive) > 0 && m.emissive_strength > 0;
  const bool black = max3(m.base_color) == 0;
  const bool lobes = (m.sheen && max3(m.sheen_color) > 0) || m.clearcoat > 0 || m.transmission > 0 || m.iridescence > 0;
  return emits && black && !lobes;
}

// The rules of docs/SCENES.md applied to one material: what it fires, the tables each rule asks for,
// the notes on what does not fire, and the ranges (clearcoat, sheen, anisotropy, films) the plan
// reports. One method per extension.
class MaterialRules {
 public:
  using Films = std::map<std::pair<double, std::string>, std::pair<Range, std::vector<std::string>>>;
  MaterialRules(Planner& p, const SceneMaterial& m, MaterialPlan& mp, Range& clearcoat_range, Range& sheen_range,
                Range& anisotropy_range, Films& films)
      : p_(p),
        m_(m),
        mp_(mp),
        who_(m.label),
        clearcoat_range_(clearcoat_range),
        sheen_range_(sheen_range),
        anisotropy_range_(anisotropy_range),
        films_(films),
        fully_metallic_(m.metallic >= 1.0 && !m.metallic_roughness_texture),
        iors_(channel_iors(m, dispersion_fires(m))),
        no_reflection_(m.ior == 1.0),
        full_reflection_(m.ior == 0.0) {}

  void apply() {
    if (m_.unlit) {
      fire(kUnlit);
      mp_.notes.push_back(std::string(kUnlit) + ": shaded by its base colour alone, nothing to bake");
      return;
    }
    if (emissive_only(m_)) {
      fire(kEmissiveOnly);
      mp_.notes.push_back("emissive-only: black base colour and no other lobe, nothing to bake for its emission");
      return;
    }
    core();
    clearcoat();
    sheen();
    anisotropy();
    ior_specular_dispersion();
    transmission();
    iridescence();
  }

 private:
  void fire(const char* rule) {
    if (std::find(mp_.rules.begin(), mp_.rules.end(), rule) == mp_.rules.end()) mp_.rules.push_back(rule);
    p_.fired(rule);
  }
  void zero(const std::string& ext, const std::string& why) {
    mp_.notes.push_back(ext + ": " + why + ", does not fire");
  }

  // metallic-roughness core
  void core() {
    fire(kCore);
    p_.ask(p_.specular_dfg(), kCore, "specular split-sum DFG (F0 scale and F90 bias)", who_);
    p_.ask(p_.prefilter("ggx"), kCore, "GGX-prefiltered radiance of the specular lobe", who_);
    const bool fully_transmissive = m_.transmission >= 1.0 && !m_.transmission_texture;
    if (!fully_metallic_ && !fully_transmissive)
      p_.ask(p_.irradiance(), kCore, "diffuse irradiance (the material is not fully metallic)", who_);
    else if (!fully_metallic_)
      mp_.notes.push_back("fully transmissive (transmissionFactor 1, no texture): no diffuse lobe, no irradiance");
  }

  void clearcoat() {
    if (!m_.clearcoat_ext) return;
    if (!(m_.clearcoat > 0)) {
      zero(kClearcoat, "clearcoatFactor 0");
      return;
    }
    fire(kClearcoat);
    const double lo = m_.clearcoat_roughness_texture ? 0.0 : m_.clearcoat_roughness;
    clearcoat_range_.add(lo, m_.clearcoat_roughness);
    p_.ask(p_.specular_dfg(), kClearcoat, "clearcoat layer: GGX DFG at the clearcoat roughness, F0 0.04", who_);
    p_.ask(p_.prefilter("ggx"), kClearcoat, "clearcoat layer: GGX-prefiltered radiance at the clearcoat roughness",
           who_);
  }

  void sheen() {
    if (!m_.sheen) return;
    if (!(max3(m_.sheen_color) > 0)) {
      zero(kSheen, "sheenColorFactor 0");
      return;
    }
    fire(kSheen);
    const double lo = m_.sheen_roughness_texture ? 0.0 : m_.sheen_roughness;
    sheen_range_.add(lo, m_.sheen_roughness);
    p_.ask(p_.dfg(TableKind::Charlie, p_.plan().options.sheen_visibility.value_or("")), kSheen,
           "sheen DFG: scales the Charlie-prefiltered radiance", who_);
    p_.ask(p_.dfg(TableKind::Charlie, "estevez-kulla"), kSheen,
           "sheen albedo E(n.v): the base layer's albedo scaling 1 - max(sheenColor) E", who_);
    p_.ask(p_.prefilter("charlie"), kSheen, "Charlie-prefiltered radiance of the sheen lobe", who_);
  }

  void anisotropy() {
    if (!m_.anisotropy_ext) return;
    if (!(m_.anisotropy_strength > 0)) {
      zero(kAnisotropy, "anisotropyStrength 0");
      return;
    }
    fire(kAnisotropy);
    anisotropy_range_.add(m_.anisotropy_texture ? 0.0 : m_.anisotropy_strength, m_.anisotropy_strength);
    p_.ask(p_.specular_dfg(), kAnisotropy, "anisotropic GGX through the isotropic DFG (bent normal)", who_);
    p_.ask(p_.prefilter("ggx"), kAnisotropy, "anisotropic GGX through the isotropic chain: the bent reflection vector",
           who_);
  }

  // Fresnel tables for the IORs in use.
  void fresnel_pair(const char* rule, const std::string& why) {
    p_.ask(p_.fresnel("dielectric", iors_, 1.0, false), rule,
           "exact dielectric Fresnel at IOR " + ior_text(iors_) + why, who_);
    p_.ask(p_.fresnel("schlick-ior", iors_, 1.0, true), rule,
           "Schlick's approximation at IOR " + ior_text(iors_) + " and its error against the exact dielectric", who_);
  }
  void trivial_ior_note(const std::string& ext) {
    if (no_reflection_)
      zero(ext, "ior 1: F = 0 everywhere, no table needed");
    else if (full_reflection_)
      zero(ext, "ior 0: F = 1 everywhere, no table needed");
  }

  void ior_specular_dispersion() {
    const SceneMaterial& m = m_;
    if (m.ior_ext) {
      if (no_reflection_ || full_reflection_) {
        trivial_ior_note(kIor);
      } else {
        fire(kIor);
        fresnel_pair(kIor, "");
      }
    }
    if (m.specular_ext) {
      if (m.specular <= 0)
        zero(kSpecular, "specularFactor 0");
      else if (max3(m.specular_color) <= 0)
        zero(kSpecular, "specularColorFactor 0");
      else if (no_reflection_ || full_reflection_)
        trivial_ior_note(kSpecular);
      else {
        fire(kSpecular);
        fresnel_pair(kSpecular, ", scaled by specularColor and specularFactor");
      }
    }
    if (m.dispersion_ext) {
      if (m.dispersion <= 0)
        zero(kDispersion, "dispersion 0");
      else if (m.transmission <= 0 || !m.volume_ext || m.thickness <= 0)
        zero(kDispersion, "no volumetric transmission (it needs transmission and a volume)");
      else if (no_reflection_)
        zero(kDispersion, "ior 1: no spread, F = 0");
      else if (full_reflection_)
        zero(kDispersion, "ior 0: F = 1, no refraction");
      else {
        fire(kDispersion);
        fresnel_pair(kDispersion, " (red, green, blue)");
      }
    }
  }

  void transmission() {
    const SceneMaterial& m = m_;
    if (!m.transmission_ext) {
      if (m.volume_ext) zero(kVolume, "no KHR_materials_transmission");
      return;
    }
    if (m.transmission <= 0) {
      zero(kTransmission, "transmissionFactor 0");
      if (m.volume_ext) zero(kVolume, "no transmission");
      return;
    }
    fire(kTransmission);
    p_.ask(p_.specular_dfg(), kTransmission, "transmitted fraction 1 - (F0 scale + F90 bias)", who_);
    p_.ask(p_.prefilter("ggx"), kTransmission,
           "refracted radiance: the chain sampled along the refracted direction at the IOR-scaled roughness", who_);
    if (no_reflection_ || full_reflection_) {
      trivial_ior_note(kTransmission);
      return;
    }
    p_.ask(p_.fresnel("dielectric", iors_, 1.0, false), kTransmission,
           "entering the surface: transmittance 1 - F at IOR " + ior_text(iors_), who_);
    if (m.volume_ext && (m.thickness > 0))
      volume();
    else if (m.volume_ext)
      zero(kVolume, "thicknessFactor 0 (thin-walled)");
  }

  void volume() {
    fire(kVolume);
    if (iors_.size() == 1) {
      p_.ask(p_.fresnel("dielectric", {1.0}, iors_[0], false), kVolume,
             "leaving the volume: F from inside (IOR " + num(iors_[0]) +
                 " to air), total internal reflection past the critical angle",
             who_);
      return;
    }
    // Per channel the relative index is 1 / n (the outside index of a table is one number).
    std::vector<double> inverse;
    for (double n : iors_) inverse.push_back(round_ior(1.0 / n));
    p_.ask(p_.fresnel("dielectric", inverse, 1.0, false), kVolume,
           "leaving the volume: F from inside (IOR " + ior_text(iors_) +
               " to air, as relative indices 1/n), total internal reflection past each channel's critical angle",
           who_);
  }

  void iridescence() {
    const SceneMaterial& m = m_;
    if (!m.iridescence_ext) return;
    // Without a thickness texture the film is iridescenceThicknessMaximum thick.
    const double lo = m.iridescence_thickness_texture ? m.iridescence_thickness_min : m.iridescence_thickness_max;
    const double hi = m.iridescence_thickness_max;
    if (m.iridescence <= 0) {
      zero(kIridescence, "iridescenceFactor 0");
      return;
    }
    if (std::max(lo, hi) <= 0) {
      zero(kIridescence, "film thickness 0");
      return;
    }
    fire(kIridescence);
    const double film = round_ior(m.iridescence_ior);
    auto add = [&](const std::string& base) {
      auto& f = films_[{film, base}];
      f.first.add(std::min(lo, hi), std::max(lo, hi));
      if (std::find(f.second.begin(), f.second.end(), who_) == f.second.end()) f.second.push_back(who_);
    };
    if (!fully_metallic_) add("base_ior=" + num(m.ior == 0.0 ? 1.5 : round_ior(m.ior)));
    if (m.metallic > 0 || m.metallic_roughness_texture) {
      if (m.base_color_texture) {
        mp_.notes.push_back(std::string(kIridescence) +
                            ": metallic part over a base colour texture: the film over the metal depends on the "
                            "texel's F0, evaluated at run time (not tabulated)");
      } else {
        add("base_f0=" + num(m.base_color[0]) + "," + num(m.base_color[1]) + "," + num(m.base_color[2]));
      }
    }
  }

  Planner& p_;
  const SceneMaterial& m_;
  MaterialPlan& mp_;
  const std::string& who_;
  Range &clearcoat_range_, &sheen_range_, &anisotropy_range_;
  Films& films_;
  const bool fully_metallic_;
  const std::vector<double> iors_;
  const bool no_reflection_;    // ior 1: F = 0 everywhere
  const bool full_reflection_;  // the extension's special value 0: F = 1
};

void apply_rules(Planner& p, const SceneMaterial& m, MaterialPlan& mp, Range& clearcoat_range, Range& sheen_range,
                 Range& anisotropy_range, MaterialRules::Films& films) {
  MaterialRules(p, m, mp, clearcoat_range, sheen_range, anisotropy_range, films).apply();
}

MaterialPlan describe(const SceneMaterial& m, bool counted) {
  MaterialPlan mp;
  mp.label = m.label;
  mp.reached_by = m.index < 0                 ? "default"
                  : m.by_mesh && m.by_variant ? "mesh+variant"
                  : m.by_mesh                 ? "mesh"
                  : m.by_variant              ? "variant"
                                              : "unreferenced";
  mp.counted = counted;
  return mp;
}

}  // namespace

Plan plan_scene(const Scene& scene, const PlanOptions& options) {
  Planner p(options);
  p.plan().job.scene = scene.path;
  p.plan().job.warnings = scene.warnings;
  Range clearcoat, sheen, anisotropy;
  std::map<std::pair<double, std::string>, std::pair<Range, std::vector<std::string>>> films;

  std::vector<const SceneMaterial*> all;
  for (const auto& m : scene.materials) all.push_back(&m);
  if (scene.default_material) all.push_back(&*scene.default_material);
  for (const SceneMaterial* m : all) {
    // A scene with meshes uses what they (and their variants) reach; a file of materials alone
    // (no meshes) is a material library: every material counts.
    const bool counted = !scene.has_meshes || m->by_mesh || m->by_variant;
    MaterialPlan mp = describe(*m, counted);
    if (counted)
      apply_rules(p, *m, mp, clearcoat, sheen, anisotropy, films);
    else
      mp.notes.push_back("not referenced by any mesh primitive or variant: not planned");
    p.plan().materials.push_back(std::move(mp));
  }

  // Thin-film tables: one per (film IOR, base), over the thicknesses its materials span.
  for (const auto& [key, value] : films) {
    const auto& [film, base] = key;
    const Range& r = value.first;
    const auto eq = base.find('=');
    const std::string base_key = base.substr(0, eq);
    ParamValue base_value;
    if (base_key == "base_ior") {
      base_value = std::stod(base.substr(eq + 1));
    } else {
      std::vector<double> f0;
      std::string rest = base.substr(eq + 1);
      size_t at = 0;
      while (at <= rest.size()) {
        const size_t comma = rest.find(',', at);
        f0.push_back(std::stod(rest.substr(at, comma - at)));
        if (comma == std::string::npos) break;
        at = comma + 1;
      }
      base_value = f0;
    }
    const std::string over = base_key == "base_ior" ? "a dielectric base of IOR " + base.substr(eq + 1)
                                                    : "a metal base of F0 " + base.substr(eq + 1);
    for (const std::string& who : value.second)
      p.ask(p.thin_film(film, base_key, base_value, r.lo, r.hi), kIridescence,
            "thin-film interference Fresnel (Belcour & Barla 2017), film IOR " + num(film) + " over " + over, who);
  }

  if (!clearcoat.empty()) p.note_rule(kClearcoat, "clearcoat roughness " + clearcoat.text());
  if (!sheen.empty()) p.note_rule(kSheen, "sheen roughness " + sheen.text());
  if (!anisotropy.empty())
    p.note_rule(kAnisotropy,
                "anisotropy strength " + anisotropy.text() + "; the isotropic tables serve (docs/SCENES.md)");
  p.finish();
  Plan plan = std::move(p.plan());
  int counted = 0, variant_only = 0;
  for (const auto& m : plan.materials) {
    counted += m.counted;
    variant_only += m.reached_by == "variant";
  }
  plan.job.notes.push_back(
      std::to_string(counted) + " of " + std::to_string(plan.materials.size()) + " materials planned" +
      (variant_only ? " (" + std::to_string(variant_only) + " reached only through variants)" : std::string()));
  if (plan.job.tables.empty()) plan.job.notes.push_back("no material calls for a table: nothing to bake");
  return plan;
}

Plan plan_default(const PlanOptions& options) {
  Planner p(options);
  const std::string who;  // no scene: no materials
  const char* rule = "default";
  p.ask(p.specular_dfg(), rule, "specular split-sum DFG of metallic-roughness materials", who);
  p.ask(p.prefilter("ggx"), rule, "GGX-prefiltered radiance of the specular lobe", who);
  p.ask(p.irradiance(), rule, "diffuse irradiance", who);
  p.finish();
  Plan plan = std::move(p.plan());
  plan.rules_fired = {rule};
  plan.job.notes.push_back("no scene: the standard set for metallic-roughness materials");
  return plan;
}

std::string plan_to_json(const Plan& plan) {
  nlohmann::ordered_json o = detail::job_json(plan.job);
  nlohmann::ordered_json p;
  p["energy_compensation"] = plan.options.energy_compensation;
  p["rules_fired"] = plan.rules_fired;
  nlohmann::ordered_json mats = nlohmann::ordered_json::array();
  for (const auto& m : plan.materials) {
    nlohmann::ordered_json e;
    e["material"] = m.label;
    e["reached_by"] = m.reached_by;
    e["counted"] = m.counted;
    e["rules"] = m.rules;
    if (!m.notes.empty()) e["notes"] = m.notes;
    mats.push_back(e);
  }
  p["materials"] = mats;
  o["plan"] = p;
  return io::json_text(o) + "\n";
}

// ---- Options as parameters -------------------------------------------------------------------------

namespace {

// A planner option that sets a table parameter: the parameter's definition under the option's name,
// with the option's own aliases (a table's aliases are its command's old spellings: prefilter's
// --size is bake's --chain-size, not bake's --size). The name is the parameter's own wherever one
// name can serve both (docs/SCENES.md, "One name per meaning"); a table's plain "size" is prefixed
// with its table, bake having several.
ParamDef from_table(TableKind kind, const char* param, const char* name, const std::string& help,
                    std::vector<std::string> aliases = {}) {
  ParamDef d = *find_param_def(table_schema(kind), param);
  d.aliases = std::move(aliases);
  d.name = name;
  d.help = help;
  d.fallback.reset();  // unset: the table's own default
  if (const ParamDef* t = find_param_def(table_schema(kind), param); t && t->fallback)
    d.default_text = param_value_text(*t->fallback);
  return d;
}

}  // namespace

const std::vector<ParamDef>& plan_schema() {
  static const PlanOptions d;
  static const std::vector<ParamDef> s = {
      ParamDef("energy_compensation", ParamType::Flag,
               "bake ggx-multiscatter (Kulla & Conty energy compensation) instead of the ggx DFG table")
          .def(d.energy_compensation),
      from_table(TableKind::GgxMultiscatter, "size", "lut_size", "DFG tables: cells along n_dot_v and roughness"),
      from_table(TableKind::Prefilter, "chain_size", "chain_size", "prefiltered chains: face size of level 0",
                 {"cube_size"}),
      from_table(TableKind::Prefilter, "min_size", "min_size", "prefiltered chains: face size of the smallest level"),
      from_table(TableKind::Prefilter, "schedule", "schedule", "prefiltered chains: roughness of each level"),
      ParamDef("chain_max_error", ParamType::Number,
               "prefiltered chains: refine each level until successive refinements differ by less (RMS); 0: fixed "
               "refinement, no measured bound")
          .range(0, 1)
          .def(d.chain_max_error)
          .alias("prefilter_max_error"),
      from_table(TableKind::Fresnel, "size", "fresnel_size", "Fresnel tables: cells along cos_theta"),
      from_table(TableKind::ThinFilm, "size", "thin_film_size",
                 "thin-film tables: cells along cos_theta and thickness"),
      from_table(TableKind::Irradiance, "sh_order", "sh_order", "irradiance: SH bands, 3 or 5", {"sh"}),
      [] {
        ParamDef w =
            from_table(TableKind::Irradiance, "sh_window", "sh_window", "irradiance: the SH window against ringing");
        w.default_text = "the target's, else none";
        return w;
      }(),
      ParamDef("engine_name", ParamType::Name,
               "NAME of an engine target's files (NAME_ibl.ktx, NAME.env, NAME.gltf; letters, digits, '.', '_', "
               "'-'); default: the output folder's name"),
      from_table(TableKind::Charlie, "sheen_visibility", "sheen_visibility", "the Charlie DFG table's visibility"),
      ParamDef("target", ParamType::Name,
               "write an engine's file set too (docs/ENGINES.md), with its schedule, sizes and SH window")
          .one_of(engine_target_names())
          .def(d.target),
      ParamDef("table_format", ParamType::Name, "1-D and 2-D tables: the file format")
          .one_of({"exr", "png", "hdr", "ktx2", "csv", "h"})
          .def(d.table_format),
      ParamDef("cube_format", ParamType::Name, "prefiltered chains: the container")
          .one_of({"ktx2", "ktx", "dds"})
          .def(d.cube_format),
      ParamDef("clamp_f16", ParamType::Flag,
               "binary16 outputs: clamp values beyond 65504 to 65504 (counted, recorded as f16_clamped, warned "
               "about) instead of refusing them (a sun in an unclipped HDR)")
          .def(d.clamp_f16),
  };
  return s;
}

}  // namespace brdfbake
