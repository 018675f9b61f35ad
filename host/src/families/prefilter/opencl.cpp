// The prefiltered chain on an OpenCL device: an environment converted to a cube on the device
// (env/conversion.cpp) while the filter's program builds, then the chain (chain.cpp); and the
// family's OpenCL kernel (kernel.hpp).
#include <chrono>
#include <functional>
#include <future>
#include <string>

#include "brdfbake/environment.hpp"
#include "env/cube.hpp"
#include "families/prefilter/kernel.hpp"
#include "families/prefilter/model.hpp"
#include "runtime/launch.hpp"

namespace brdfbake {

namespace {

class OpenClPrefilter final : public detail::PrefilterKernel {
 public:
  explicit OpenClPrefilter(Device& device) : device_(device) {}
  CubeLevels bake(const EnvImage& env, const PrefilterSpec& spec, PrefilterTiming* timing, const EnvProgress& progress,
                  const std::function<void()>& source_done) override {
    return prefilter_environment(device_, env, spec, timing, progress, source_done);
  }

 private:
  Device& device_;
};

}  // namespace

std::unique_ptr<detail::PrefilterKernel> detail::make_opencl_prefilter(Device& device) {
  return std::make_unique<OpenClPrefilter>(device);
}

CubeLevels prefilter_cube(Device& device, const CubeLevels& source, const PrefilterSpec& in, PrefilterTiming* timing,
                          const EnvProgress& progress) {
  return detail::prefilter_chain(device, source, in, timing, progress);
}

CubeLevels prefilter_environment(Device& device, const EnvImage& env, const PrefilterSpec& in, PrefilterTiming* timing,
                                 const EnvProgress& progress, const std::function<void()>& source_done) {
  const auto t0 = std::chrono::steady_clock::now();
  const PrefilterSpec s = resolve_prefilter_spec(in);
  if (progress) progress(0.0, "converting to a cube");
  double convert_seconds = 0.0;
  // the filter's program is built (or read from the cache) while the conversion runs
  std::future<void> filter_built;
  CubeLevels source = detail::convert_to_cube(
      device, env, s.size, &convert_seconds,
      [&] {
        filter_built = std::async(std::launch::async, [&device, &s] {
          detail::cl_call("building kernels/prefilter.cl", [&] { return detail::filter_program(device.impl(), s), 0; });
        });
      },
      source_done);  // the pixels are not read again
  if (filter_built.valid()) filter_built.get();
  PrefilterTiming t;
  t.device_seconds = convert_seconds;
  t.stage_seconds.emplace_back("convert", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  CubeLevels out = detail::prefilter_chain(device, std::move(source), s, &t, progress);
  detail::environment_source_metadata(out, env);
  if (timing) {
    *timing = t;
    if (!timing->level_device_seconds.empty()) timing->level_device_seconds[0] += convert_seconds;
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return out;
}

}  // namespace brdfbake
