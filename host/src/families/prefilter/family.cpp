// The prefilter family (kind prefilter): a GGX or Charlie prefiltered radiance mip chain of the
// environment. Its descriptor: the schema bound to PrefilterSpec, the rules across fields (an
// engine target's conventions), names, the bake (radiance near FLT_MAX scaled into headroom) and
// the registration of its kernels. Engine: chain.cpp and the files model.hpp lists, with the
// environment families' shared engine in host/src/env/; kernels: opencl.cpp (kernels/prefilter.cl),
// reference.cpp (host/reference/src/prefilter.cpp); tests: tests/device/test_prefilter.cpp,
// tests/reference/test_envmap_reference.cpp.
#include "families/family.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"
#include "env/cube.hpp"
#include "families/delivery.hpp"
#include "families/kernels.hpp"
#include "families/prefilter/bound_kernel.hpp"
#include "families/prefilter/kernel.hpp"
#include "families/prefilter/model.hpp"
#include "families/spec_schema.hpp"

namespace brdfbake::detail {

namespace {

// The schema, bound to PrefilterSpec.
SpecSchema<PrefilterSpec> make_prefilter_schema() {
  static const PrefilterSpec d;
  using T = ParamType;
  using S = PrefilterSpec;
  SpecSchema<PrefilterSpec> s;
  s.bind(&S::distribution, "distribution",
         ParamDef("distribution", T::Name, "the lobe each level is filtered with")
             .one_of(enum_names(kEnvDistributionNames))
             .def(std::string(env_distribution_name(d.distribution))),
         by_name(env_distribution_from_name))
      .bind(&S::size, "size",
            ParamDef("chain_size", T::Int, "face size of level 0 (the source cube)")
                .range(1, kPrefilterMaxSize)
                .def(double(d.size))
                .alias("size"))
      .bind(&S::min_size, "min_size",
            ParamDef("min_size", T::Int, "face size of the smallest level")
                .range(1, kPrefilterMaxSize)
                .def(double(d.min_size)))
      .bind(
          &S::schedule, "schedule",
          ParamDef("schedule", T::Name, "roughness of level l: linear (Khronos), filament, sqrt, babylon (Babylon.js)")
              .one_of(enum_names(kRoughnessScheduleNames))
              .def(std::string(roughness_schedule_name(d.schedule))),
          by_name(roughness_schedule_from_name))
      .bind(&S::estimator, "estimator",
            ParamDef("estimator", T::Name,
                     "quadrature (deterministic) | sampling (importance sampling with filtered importance sampling)")
                .one_of(enum_names(kEnvEstimatorNames))
                .def(std::string(env_estimator_name(d.estimator))),
            by_name(env_estimator_from_name))
      .bind(&S::samples, "samples",
            ParamDef("samples", T::Int, "sampling: lobe samples per texel of every level")
                .range(1, kPrefilterMaxSamples)
                .defaults_to("1024"))
      .bind(&S::max_error, "max_error",
            ParamDef(
                "chain_max_error", T::Number,
                "refine each level (quadrature) or choose samples (sampling) until successive estimates differ by less "
                "(RMS relative luminance)")
                .above(0, 1)
                .alias("max_error"))
      .bind(&S::refinement, "refinement",
            ParamDef("refinement", T::Number,
                     "quadrature: refine pyramid texels within this many texel sizes of the lobe's centre (not with "
                     "chain_max_error)")
                .range(1.5, 64)
                .defaults_to(fmt_number(d.refinement)))
      .bind("bright_texels",
            ParamDef("env_sampling", T::Flag, "sum the brightest texels (suns) exactly").def(d.bright_texels != 0),
            [](PrefilterSpec& p, const TableRequest& t) {
              if (!t.flag("env_sampling", true)) p.bright_texels = 0;
            })
      .bind(&S::filtered_importance_sampling, "filtered_importance_sampling",
            ParamDef("fis", T::Flag, "sampling: filtered importance sampling (off: every sample reads level 0)")
                .def(d.filtered_importance_sampling))
      .bind(&S::clamp_luminance, "clamp_luminance",
            ParamDef("clamp", T::Number, "BIASED, opt-in: compress source luminance above this value").above(0))
      .param(ParamDef("target", T::Name,
                      "an engine's conventions (docs/ENGINES.md): its schedule and sizes unless given; "
                      "bake --target writes its whole file set")
                 .one_of(engine_target_names())
                 .def(std::string("generic")))
      .common("precision", "precision", [](PrefilterSpec& p, const TableRequest& t) { p.precision = t.precision; })
      .internal("core_refinement", "quadrature shape: measured by the bench")
      .internal("horizon_texel", "quadrature shape: measured by the bench")
      .internal("strips", "the per-texel walk: the accuracy reference of the bench and tests")
      .internal("lod_bias", "measured by the bench (0 is best here)");
  std::vector<ParamDef> output;
  add_cube_output_params(output);
  return s.params(output);
}

const SpecSchema<PrefilterSpec>& prefilter_schema() {
  static const SpecSchema<PrefilterSpec> s = make_prefilter_schema();
  return s;
}

class PrefilterFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override { return {TableKind::Prefilter}; }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    // RGBA float texels (16 bytes): the source cube and its mips on the host and on the device, the
    // chain on the device, on the host and in the writer's encoding.
    const double size = t.number("chain_size"), min_size = std::max(1.0, t.number("min_size", 1));
    double chain = 0;
    for (double s = size; s >= min_size; s = std::floor(s / 2)) {
      chain += 6 * s * s;
      if (s <= 1) break;
    }
    const double source = 6 * size * size * 4.0 / 3.0;
    return static_cast<std::uint64_t>(16 * (2 * source + 3 * chain)) + (std::uint64_t(1) << 20);
  }
  std::string command() const override { return "prefilter"; }
  TableExample example(TableKind) const override {
    TableExample e;
    e.request.environment = "builtin:sun";
    e.request.params = {{"chain_size", 8.0}, {"min_size", 4.0}};
    return e;
  }
  CommandText command_text() const override {
    return {"prefilter an environment into a GGX or Charlie radiance mip chain",
            "Prefilter an environment into a GGX or Charlie radiance mip chain",
            "brdfbake prefilter --env studio.hdr --chain-size 256 --distribution ggx -o studio_ggx.ktx2"};
  }
  std::string summary(TableKind) const override {
    return "a prefiltered radiance mip chain of an environment (GGX or Charlie lobe per level)";
  }
  bool uses_environment() const override { return true; }

  const std::vector<ParamDef>& schema(TableKind) const override { return prefilter_schema().schema(); }
  std::vector<SpecField> spec_fields(TableKind) const override { return prefilter_schema().fields(); }
  void register_kernels(KernelRegistry& r) const override {
    r.add<PrefilterKernel>(Platform::OpenCl, [](Backend& b) { return make_opencl_prefilter(*b.device()); });
    r.add<PrefilterKernel>(Platform::Reference, [](Backend&) { return make_reference_prefilter(); });
    r.add<ChainBoundKernel>(Platform::OpenCl, [](Backend& b) { return make_opencl_chain_bound(*b.device()); });
    r.add<ChainBoundKernel>(Platform::Reference, [](Backend&) { return make_reference_chain_bound(); });
  }

  void check(TableRequest& t, const FieldName& name) const override {
    if (t.text("target") != "generic") {
      // The engine's conventions where the request does not name its own.
      const EngineSettings e = engine_settings(engine_target_from_name(t.text("target")));
      if (!t.was_given("schedule")) t.set("schedule", std::string(roughness_schedule_name(e.schedule)));
      if (!t.was_given("chain_size")) t.set("chain_size", double(e.size));
      if (!t.was_given("min_size")) t.set("min_size", double(e.min_size));
      // What the engine's files hold, checked here as the bake's engine writer checks its chain
      // (engine_writers.cpp, check_chain), so that a one-table command, a job and the server refuse
      // what the file's engine metadata would misdescribe, before anything is baked.
      const std::string target = t.text("target");
      const int size = static_cast<int>(t.number("chain_size"));
      if (e.power_of_two && (size & (size - 1)) != 0)
        throw FieldError("chain_size", target + " needs a power-of-two face size (got " + std::to_string(size) + ")");
      if (t.text("schedule") != roughness_schedule_name(e.schedule))
        throw FieldError("schedule", target + " reads its levels with the '" + roughness_schedule_name(e.schedule) +
                                         "' schedule (" + e.lod_formula + "), not '" + t.text("schedule") + "'");
      if (e.min_size == 1 && t.number("min_size") != 1)
        throw FieldError("min_size",
                         target + " stores the full chain down to 1x1 (got " + fmt_number(t.number("min_size")) + ")");
    }
    if (t.find("samples") && t.text("estimator") != "sampling")
      throw FieldError("samples", "needs " + name("estimator") + " sampling (the quadrature takes " +
                                      name("refinement") + " or " + name("chain_max_error") + ")");
    if (t.find("samples") && t.find("chain_max_error"))
      throw FieldError("chain_max_error", "give " + name("samples") + " or " + name("chain_max_error") + ", not both");
    if (t.find("refinement") && (t.find("chain_max_error") || t.text("estimator") != "quadrature"))
      throw FieldError("refinement", t.find("chain_max_error") ? "give " + name("refinement") + " or " +
                                                                     name("chain_max_error") + ", not both"
                                                               : "applies to " + name("estimator") + " quadrature");
    if (t.number("min_size") > t.number("chain_size"))
      throw FieldError("min_size", "must be at most " + name("chain_size") + " (got " +
                                       fmt_number(t.number("min_size")) + " > " + fmt_number(t.number("chain_size")) +
                                       ")");
    if (!t.flag("fis") && t.text("estimator") != "sampling")
      throw FieldError("fis", "applies to " + name("estimator") + " sampling");
    try {
      resolve_prefilter_spec(spec_of(t));
    } catch (const Error& e) {
      throw FieldError("", e.what());
    }
  }

  std::string default_output(const TableRequest& t) const override {
    return "prefilter_" + t.text("distribution") + "_" + fmt_number(t.number("chain_size"), "%.0f") +
           (t.format.empty() ? ".ktx2" : output_extension(t));
  }
  OutputFormats formats(const TableRequest&) const override { return cube_formats(); }
  void check_output(const TableRequest& t, const FieldName& name) const override {
    Family::check_output(t, name);
    check_cube_output(t, name);
  }

  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs& in,
                  const BakeProgress& progress) const override {
    PrefilterSpec spec = spec_of(t);
    PrefilterTiming timing;
    BakeResult r;
    EnvImage scaled;
    double scale = 1.0;
    const EnvImage& env = headroom_environment(*in.environment, scaled, &scale);
    spec.clamp_luminance /= scale;  // the opt-in clamp is a luminance: scaled with the radiance
    CubeLevels cube = prefilter_environment(backend, env, spec, &timing, progress, in.release_environment);
    spec.clamp_luminance *= scale;
    // The bound every chain records: each level against the double reference on a sample of its
    // texels (bound.cpp), before the headroom scale (the difference is relative).
    if (progress) progress(1.0, "measuring the error bound");
    const PrefilterSpec resolved = resolve_prefilter_spec(spec);
    std::vector<double> roughness;
    for (int l = 0; l < cube.level_count(); ++l)
      roughness.push_back(schedule_roughness(resolved.schedule, l, cube.level_count()));
    const ChainBound bound = chain_error_bound(backend, cube, resolved.distribution, roughness);
    if (scale != 1.0)
      for (auto& level : cube.levels)
        for (float& v : level) v = static_cast<float>(double(v) * scale);
    std::vector<std::string> level_bounds, max_text, sample_text;
    for (size_t l = 0; l < bound.per_level.size(); ++l) {
      level_bounds.push_back(bound_text(bound.per_level[l]));
      max_text.push_back(fmt_number(bound.max_difference[l], "%.3g"));
      sample_text.push_back(std::to_string(bound.samples[l]));
    }
    cube.set_meta("integration_error_bound_per_level", comma_join(level_bounds));
    cube.set_meta("integration_error_bound_definition", kChainBoundDefinition);
    cube.set_meta("max_relative_difference_per_level", comma_join(max_text));
    cube.set_meta("bound_samples_per_level", comma_join(sample_text));
    r.error_bound = chain_recorded_bound(bound, spec.max_error, timing.measured_error);
    r.error_bound_definition = std::string(kChainBoundDefinition) + "; the largest over the levels";
    if (*r.error_bound > bound.bound) {
      // the search's last difference, where it says more than the comparison
      r.error_bound_definition +=
          ", or chain_max_error's measured difference (" + fmt_number(timing.measured_error, "%.3g") + ") where larger";
    }
    // chain_max_error stops the refinement when successive refinements agree; the comparison with the
    // double reference can still measure more: said in the file, the summary and the manifest (issue 35)
    if (spec.max_error > 0 && r.error_bound && *r.error_bound > spec.max_error) {
      const std::string miss = "the chain's error bound " + fmt_number(*r.error_bound, "%.3g") +
                               " (against the double reference) is above the chain_max_error " +
                               fmt_number(spec.max_error, "%.3g") +
                               " asked: successive refinements agreed to it, the converged chain differs more";
      cube.set_meta("max_error_met", "no: " + miss);
      r.warnings.push_back(std::string(env_distribution_name(spec.distribution)) + " prefiltered chain: " + miss);
    } else if (spec.max_error > 0) {
      cube.set_meta("max_error_met", "yes: the error bound is at most the chain_max_error asked");
    }
    if (spec.estimator == EnvEstimator::Quadrature && spec.max_error <= 0)
      r.parameters.push_back({"refinement", spec.refinement});
    r.details.push_back({"levels", cube.meta("levels")});
    r.details.push_back({"lod_from_roughness", cube.meta("lod_from_roughness")});
    r.device_seconds = timing.device_seconds;
    const int levels = cube.level_count();
    r.summary = std::string(env_distribution_name(spec.distribution)) + ", " + std::to_string(levels) +
                (levels == 1 ? " level " : " levels ") + std::to_string(cube.size) + "^2 -> " +
                std::to_string(cube.level_size(levels - 1)) + "^2, " + roughness_schedule_name(spec.schedule) +
                " schedule (" + cube.meta("lod_from_roughness") + "), " + env_estimator_name(spec.estimator) + ", " +
                fmt_number(timing.wall_seconds, "%.3f") + " s (device " + fmt_number(timing.device_seconds, "%.3f") +
                " s)";
    if (timing.wall_seconds >= 1.0) {
      // long runs: the peak resident memory so far (getrusage: of the whole process, so in `serve`
      // of every job it ran)
      rusage usage{};
      if (::getrusage(RUSAGE_SELF, &usage) == 0)
        r.summary += ", peak memory " + fmt_number(double(usage.ru_maxrss) / 1024.0, "%.0f") + " MiB";
    }
    r.artifact = std::move(cube);
    return r;
  }

  WriteReport write(const BakeResult& r, const TableRequest& t, const std::string& path) const override {
    return write_cube_result(*r.cube(), t, path, "level", r.error_bound);
  }

 private:
  static PrefilterSpec spec_of(const TableRequest& t) { return prefilter_schema().fill(t); }
};

}  // namespace

const Family& prefilter_family() {
  static const PrefilterFamily f;
  return f;
}

}  // namespace brdfbake::detail
