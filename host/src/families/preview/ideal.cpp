// The preview's ideal bake (ideal.hpp).
#include "families/preview/ideal.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "brdfbake/engines.hpp"
#include "brdfbake/error.hpp"
#include "engines/registry.hpp"
#include "families/prefilter/model.hpp"
#include "families/preview/shading.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::preview {

namespace {

// Level 1 of a two-level chain as a cube of one level.
CubeLevels second_level(CubeLevels c) {
  CubeLevels one;
  one.size = c.level_size(1);
  one.levels.push_back(std::move(c.levels.at(1)));
  return one;
}

// A level's face size in the ideal chain: at least 4 x the files' level of the same index (its
// bilinear interpolation error, second order in the texel, 1/16 of theirs), texels no wider than an
// eighth of the lobe (pi/2 / S <= alpha / 8), at least kIdealMinLevelSize, at most `size` (a power
// of two).
int level_size(const CubeLevels& chain, int l, double roughness, int size) {
  const double alpha = std::max(roughness * roughness, 1e-4);
  const double want = std::max({double(kIdealMinLevelSize), 4.0 * chain.level_size(l), 4.0 * M_PI / alpha});
  int s = kIdealMinLevelSize;
  while (s < size && double(s) < want) s *= 2;
  return std::min(s, size);
}

// A chain of the files (the GGX chain, `name` "specular", or the Charlie chain, "sheen"): level l of
// the files' N at schedule_roughness(schedule, l, N), at its level_size S, filtered with
// `distribution` from the environment converted to 2 S (a chain of two levels whose second is at that
// roughness: prefilter_chain_at); level 0, the mirror, is the environment converted to 2 size.
std::vector<CubeLevels> ideal_chain(Device& device, const EnvImage& env, const CubeLevels& chain, int size,
                                    RoughnessSchedule schedule, EnvDistribution distribution, const std::string& name,
                                    const std::string& schedule_note, Metadata& settings) {
  const int n = chain.level_count();
  // The mirror: the environment converted to 2 size, but no finer than the source resolves (an
  // equirect's width / 2, twice a cube's face) unless size needs it: beyond, a conversion adds texels
  // and no detail (a 1024^2 mirror of a 1k map: 100 MB more for the bake sweep's 512^2 setting).
  const int detail = env.layout == EnvImage::Layout::Cube ? 2 * env.width : env.width / 2;
  int mirror_size = 2 * size;
  while (mirror_size > size && mirror_size / 2 >= std::max(size, detail)) mirror_size /= 2;
  // Each level's size, and how many times each converted source is used: a source is handed over
  // (not copied) at its last use and freed (the memory of a 512^2 chain's ideal bake: its 1024^2
  // source is 100 MB).
  std::vector<int> level_sizes(size_t(n), 0);
  std::map<int, int> uses{{mirror_size, 1}};
  for (int l = 1; l < n; ++l) {
    level_sizes[size_t(l)] = level_size(chain, l, schedule_roughness(schedule, l, n), size);
    ++uses[2 * level_sizes[size_t(l)]];
  }
  std::map<int, CubeLevels> sources;  // by face size
  const auto take = [&](int s) {
    auto it = sources.find(s);
    if (it == sources.end()) it = sources.emplace(s, environment_to_cube(device, env, s)).first;
    CubeLevels one;
    one.size = s;
    if (--uses[s] == 0) {
      one.levels.push_back(std::move(it->second.levels[0]));
      sources.erase(it);
    } else {
      one.levels.push_back(it->second.levels[0]);
    }
    return one;
  };
  std::vector<CubeLevels> out;
  out.push_back(take(mirror_size));
  std::string roughness, sizes = std::to_string(mirror_size);
  PrefilterSpec spec;
  spec.distribution = distribution;
  spec.schedule = schedule;
  spec.precision = Precision::Fp32;
  spec.refinement = kIdealRefinement;
  for (int l = 1; l < n; ++l) {
    const double r = schedule_roughness(schedule, l, n);
    const int s = level_sizes[size_t(l)];
    spec.size = 2 * s;
    spec.min_size = s;
    out.push_back(second_level(prefilter_chain_at(device, take(2 * s), spec, {0.0, r})));
    roughness += ", " + std::to_string(r).substr(0, 6);
    sizes += ", " + std::to_string(s);
  }
  settings.push_back({name, std::to_string(n) +
                                " levels as the files' (the engine's LOD mapping unchanged), level 0 the "
                                "environment converted to a cube, every other level filtered (" +
                                std::string(distribution == EnvDistribution::Charlie ? "Charlie" : "GGX") +
                                ") on its own from the environment converted to twice its size (quadrature, "
                                "refinement " +
                                std::to_string(int(kIdealRefinement)) + "), float32, no storage"});
  settings.push_back({name + "_sizes", sizes});
  settings.push_back({name + "_schedule", std::string(roughness_schedule_name(schedule)) + " (" + schedule_note + ")"});
  settings.push_back({name + "_roughness_per_level", "0" + roughness});
  return out;
}

// The DFG table at its texel centres' exact albedos (exact_albedos: the DFG family's quadrature at
// explicit coordinates), float32, with the files' axes and channels.
Table ideal_dfg(Backend& backend, const BakeFiles& files, int size) {
  std::vector<double> nvs(static_cast<size_t>(size)), rs(static_cast<size_t>(size));
  for (int i = 0; i < size; ++i) {
    const double u = (i + 0.5) / size;
    nvs[size_t(i)] = files.dfg_sqrt_n_dot_v ? u * u : u;
    rs[size_t(i)] = u;
  }
  const std::vector<double> ab = exact_albedos(backend, nvs, rs);
  Table t;
  t.width = t.height = size;
  t.channels =
      files.dfg_multiscatter ? std::vector<std::string>{"bias", "albedo"} : std::vector<std::string>{"scale", "bias"};
  t.x_name = "n_dot_v";
  t.y_name = "roughness";
  t.x = nvs;
  t.y = rs;
  t.data.resize(2 * size_t(size) * size_t(size));
  for (size_t k = 0; k < t.data.size() / 2; ++k) {
    const double albedo = ab[2 * k], bias = ab[2 * k + 1];
    if (files.dfg_multiscatter) {  // (bias, albedo)
      t.data[2 * k] = float(bias);
      t.data[2 * k + 1] = float(albedo);
    } else {  // (scale, bias): albedo = scale + bias
      t.data[2 * k] = float(albedo - bias);
      t.data[2 * k + 1] = float(bias);
    }
  }
  return t;
}

// The charlie table (KHR_materials_sheen's albedo scaling E(n.v, sheenRoughness)) likewise: each
// texel the exact E at its centre (sheen_albedos: the charlie table's quadrature, Estevez & Kulla's
// visibility), float32, the files' n.v axis.
Table ideal_charlie(Backend& backend, const BakeFiles& files, int size) {
  std::vector<double> nvs(static_cast<size_t>(size)), rs(static_cast<size_t>(size));
  for (int i = 0; i < size; ++i) {
    const double u = (i + 0.5) / size;
    nvs[size_t(i)] = files.charlie_sqrt_n_dot_v ? u * u : u;
    rs[size_t(i)] = u;
  }
  const std::vector<double> e = sheen_albedos(backend, nvs, rs);
  Table t;
  t.width = t.height = size;
  t.channels = {files.charlie.channels.empty() ? std::string("albedo") : files.charlie.channels[0]};
  t.x_name = "n_dot_v";
  t.y_name = "sheen_roughness";
  t.x = nvs;
  t.y = rs;
  t.data.assign(e.begin(), e.end());
  return t;
}

}  // namespace

std::string ideal_parts_key(const BakeFiles& files) {
  // What ideal_chain, ideal_dfg and ideal_charlie read of the files.
  std::string k = std::string(engine_target_name(files.target)) + " levels";
  for (int l = 0; l < files.specular.level_count(); ++l) k += " " + std::to_string(files.specular.level_size(l));
  if (!files.sheen.levels.empty()) {
    k += " sheen levels";
    for (int l = 0; l < files.sheen.level_count(); ++l) k += " " + std::to_string(files.sheen.level_size(l));
  }
  if (!engines::target_def(files.target).engine_dfg)
    k += files.dfg_multiscatter ? " dfg multiscatter" : " dfg single",
        k += files.dfg_sqrt_n_dot_v ? " sqrt" : " linear";
  if (files.diffuse == DiffuseSource::IrradianceCube) k += " irradiance " + std::to_string(files.irradiance.size);
  if (files.charlie.width > 0)
    k += " charlie " + files.charlie_visibility + (files.charlie_sqrt_n_dot_v ? " sqrt" : " linear") + " " +
         (files.charlie.channels.empty() ? std::string("albedo") : files.charlie.channels[0]);
  return k;
}

IdealParts ideal_parts(Backend& backend, const EnvImage& environment, const BakeFiles& files) {
  const auto t0 = std::chrono::steady_clock::now();
  Device* device = backend.device();
  if (!device) throw Error("the ideal bake (the error's shares) filters its chain on an OpenCL device");
  IdealParts out;
  out.key = ideal_parts_key(files);
  const int size = std::clamp(files.specular.size, kIdealChainSize, kIdealChainMaxSize);
  out.specular_levels = ideal_chain(*device, environment, files.specular, size, engine_settings(files.target).schedule,
                                    EnvDistribution::Ggx, "specular", "the target's", out.settings);
  const double chain_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.settings.push_back({"specular_seconds", std::to_string(chain_seconds).substr(0, 6)});
  if (engines::target_def(files.target).engine_dfg) {
    out.settings.push_back({"dfg", "the engine's own table (" + file_name(files.dfg_file) + "): no file changes it"});
  } else {
    out.dfg = ideal_dfg(backend, files, kIdealLutSize);
    out.settings.push_back({"dfg", std::to_string(kIdealLutSize) +
                                       "^2 float32, each texel the exact albedos at its "
                                       "centre (the DFG family's quadrature), the files' axes and channels"});
  }
  if (files.diffuse == DiffuseSource::IrradianceCube) {
    // the Lambertian cube (khronos-viewer): the irradiance family's at 4 x the files' face size
    IrradianceSpec spec;
    spec.cube_size = std::min(std::max(kIdealIrradianceSize, 2 * files.irradiance.size), kIrradianceMaxCube);
    spec.source_size = kIdealIrradianceSource;
    out.irradiance = compute_irradiance(backend, environment, spec).cube;
    out.settings.push_back({"diffuse", "the Lambertian cube " + std::to_string(spec.cube_size) +
                                           "^2 float32 (the irradiance family's, from the environment converted "
                                           "to " +
                                           std::to_string(spec.source_size) + "^2), no storage"});
  } else {
    out.settings.push_back({"diffuse", ""});  // the files' own: apply_ideal_parts names them
  }
  // KHR_materials_sheen: the charlie table where its visibility is the reference's (Estevez & Kulla);
  // the Charlie chain stays the files'
  if (files.charlie.width > 0 && (files.charlie_visibility.empty() || files.charlie_visibility == "estevez-kulla")) {
    out.charlie = ideal_charlie(backend, files, kIdealLutSize);
    out.settings.push_back({"charlie", std::to_string(kIdealLutSize) +
                                           "^2 float32, each texel the exact sheen albedo "
                                           "at its centre (the charlie table's quadrature), the files' n.v axis"});
  } else if (files.charlie.width > 0) {
    out.settings.push_back({"charlie", "the files' own (" + files.charlie_visibility + " visibility, not replaced)"});
  }
  // the Charlie chain: every target that samples one reads level sheenRoughness (levels - 1)
  // (engines/generic and khronos_viewer/splitsum.cpp): the linear schedule
  if (!files.sheen.levels.empty()) {
    const auto t1 = std::chrono::steady_clock::now();
    out.sheen_levels =
        ideal_chain(*device, environment, files.sheen,
                    std::clamp(files.sheen.size, kIdealChainSize, kIdealChainMaxSize), RoughnessSchedule::Linear,
                    EnvDistribution::Charlie, "sheen", "the lookup's: lod = sheenRoughness (levels - 1)", out.settings);
    out.settings.push_back(
        {"sheen_seconds",
         std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count()).substr(0, 6)});
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.settings.push_back({"seconds", std::to_string(out.seconds).substr(0, 6)});
  return out;
}

IdealBake apply_ideal_parts(const IdealParts& parts, const BakeFiles& files) {
  if (parts.key != ideal_parts_key(files))
    throw Error("internal: an ideal bake made for other files (" + parts.key + ") applied to " +
                ideal_parts_key(files));
  IdealBake out;
  out.files = files;
  out.files.folder = "the ideal bake (in memory)";
  out.files.specular_levels = parts.specular_levels;
  out.files.specular_format = "float32 (the ideal bake)";
  if (parts.dfg.width > 0) {
    out.files.dfg = parts.dfg;
    out.files.dfg_file = "the ideal DFG table";
  }
  if (!parts.sheen_levels.empty()) out.files.sheen_levels = parts.sheen_levels;
  if (!parts.irradiance.levels.empty()) {
    out.files.irradiance = parts.irradiance;
    out.files.diffuse_file = "the ideal Lambertian cube";
  }
  if (parts.charlie.width > 0) {
    out.files.charlie = parts.charlie;
    out.files.charlie_file = "the ideal charlie table";
  }
  out.settings = parts.settings;
  for (auto& [key, value] : out.settings)
    if (key == "diffuse" && value.empty())
      value = files.diffuse == DiffuseSource::None ? std::string("none, as the files (no irradiance baked)")
                                                   : "the files' own (" + file_name(files.diffuse_file) + ")";
  out.seconds = parts.seconds;
  return out;
}

IdealBake ideal_bake(Backend& backend, const EnvImage& environment, const BakeFiles& files) {
  return apply_ideal_parts(ideal_parts(backend, environment, files), files);
}

}  // namespace brdfbake::detail::preview
