// The prefiltered radiance chain on the reference backend: prefilter_environment_reference, every
// level by the brute-force double reference (host/reference/src/prefilter.cpp, prefilter_cube),
// and the family's reference kernel (kernel.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "env/cube.hpp"
#include "env/reference_cube.hpp"
#include "families/prefilter/kernel.hpp"
#include "families/prefilter/model.hpp"

namespace brdfbake {
namespace {

reference::EnvLobe to_lobe(EnvDistribution d) {
  return d == EnvDistribution::Charlie ? reference::EnvLobe::Charlie : reference::EnvLobe::Ggx;
}

std::string fmt(double v, const char* f = "%.3g") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// The sub-cells per source texel side of each level (0 for level 0, the source itself).
std::vector<int> subdivisions(const PrefilterSpec& s, int levels) {
  std::vector<int> q(static_cast<size_t>(levels), 0);
  for (int l = 1; l < levels; ++l) {
    const double r = schedule_roughness(s.schedule, l, levels);
    q[size_t(l)] = reference::env_default_subdivision(to_lobe(s.distribution), r * r, s.size);
  }
  return q;
}

class ReferencePrefilter final : public detail::PrefilterKernel {
 public:
  CubeLevels bake(const EnvImage& env, const PrefilterSpec& spec, PrefilterTiming* timing, const EnvProgress& progress,
                  const std::function<void()>&) override {
    return prefilter_environment_reference(env, spec, timing, progress);
  }
};

}  // namespace

std::unique_ptr<detail::PrefilterKernel> detail::make_reference_prefilter() {
  return std::make_unique<ReferencePrefilter>();
}

double prefilter_reference_work(const PrefilterSpec& in) {
  const PrefilterSpec s = resolve_prefilter_spec(in);
  const int levels = prefilter_level_count(s);
  const std::vector<int> q = subdivisions(s, levels);
  const double source_cells = 6.0 * s.size * s.size;
  double work = 0.0;
  for (int l = 1; l < levels; ++l) {
    const double size = std::max(1, s.size >> l);
    work += 6.0 * size * size * source_cells * q[size_t(l)] * q[size_t(l)];
  }
  return work;
}

CubeLevels prefilter_environment_reference(const EnvImage& env, const PrefilterSpec& in, PrefilterTiming* timing,
                                           const EnvProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const PrefilterSpec s = resolve_prefilter_spec(in);
  const double work = prefilter_reference_work(s);
  if (work > kPrefilterReferenceMaxWork)
    throw Error("the scalar reference would evaluate " + fmt(work) + " lobe terms for this chain (size " +
                std::to_string(s.size) + ", min size " + std::to_string(s.min_size) + "), above its limit of " +
                fmt(kPrefilterReferenceMaxWork) +
                " (a few seconds): use an OpenCL device (--device), or a smaller size or fewer levels");
  const int levels = prefilter_level_count(s);
  const std::vector<int> q = subdivisions(s, levels);
  if (progress) progress(0.0, "converting to a cube");

  CubeLevels out;
  out.size = s.size;
  out.levels.resize(static_cast<size_t>(levels));
  out.levels[0] = detail::to_rgba(detail::reference_source_cube(env, s.size));
  if (s.clamp_luminance > 0.0) detail::clamp_luminance(out.levels[0], s.clamp_luminance);
  // every level filters the stored level 0, as the device's
  const reference::EnvCube source = detail::to_reference_cube(out.levels[0], s.size);

  std::vector<double> roughness(static_cast<size_t>(levels), 0.0), seconds(static_cast<size_t>(levels), 0.0);
  for (int l = 0; l < levels; ++l) roughness[size_t(l)] = schedule_roughness(s.schedule, l, levels);
  seconds[0] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (int l = 1; l < levels; ++l) {
    if (progress)
      progress(double(l - 1) / double(levels - 1), "level " + std::to_string(l) + "/" + std::to_string(levels - 1));
    const auto tl = std::chrono::steady_clock::now();
    const reference::EnvCube level = reference::prefilter_cube(source, to_lobe(s.distribution), roughness[size_t(l)],
                                                               out.level_size(l), q[size_t(l)]);
    out.levels[size_t(l)] = detail::to_rgba(level);
    seconds[size_t(l)] = std::chrono::duration<double>(std::chrono::steady_clock::now() - tl).count();
  }
  if (progress) progress(1.0, "done");

  detail::prefilter_metadata(out, s, roughness);
  out.set_meta("estimator", "reference");
  std::vector<std::string> q_text;
  for (int v : q) q_text.push_back(std::to_string(v));
  out.set_meta("subdivision_per_level", detail::comma_join(q_text));
  out.set_meta("estimator_description",
               "brute force in double (the scalar reference): every output texel sums K(R.l) L(l) Omega over every "
               "source texel split into q x q sub-cells of exact solid angle (q per level in subdivision_per_level), "
               "normalised by the same sum of K Omega; level 0 converted by the mean of the source's bilinear "
               "interpolation over " +
                   std::to_string(detail::reference_conversion_subdivision(env, s.size)) + " x " +
                   std::to_string(detail::reference_conversion_subdivision(env, s.size)) + " sub-cells per texel");
  if (s.clamp_luminance > 0.0)
    out.set_meta("clamp", "BIASED: source luminance above " + fmt(s.clamp_luminance, "%.6g") +
                              " compressed to limit (1 + log(lum / limit))");
  out.set_meta("precision", "fp64");
  out.set_meta("device", "reference (scalar double)");
  detail::environment_source_metadata(out, env);
  if (timing) {
    timing->level_device_seconds = seconds;
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timing->device_seconds = timing->wall_seconds;
  }
  return out;
}

std::vector<double> detail::prefilter_reference_directions(const CubeLevels& source, EnvDistribution distribution,
                                                           double roughness, const std::vector<Vec3>& directions) {
  const reference::EnvCube src = detail::to_reference_cube(source.levels.at(0), source.size);
  return reference::prefilter_directions(src, to_lobe(distribution), roughness, directions);
}

}  // namespace brdfbake
