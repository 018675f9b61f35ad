// The reference render on the reference backend: every pixel by the scalar double brute force of
// host/reference/src/preview.cpp (subdivision 16; the bound's pixels at 32). Practical for small
// requests only: the work, pixels x the environment's pixels, is bounded by kPreviewReferenceMaxWork.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/reference/preview.hpp"
#include "families/preview/kernel.hpp"

namespace brdfbake::detail {

namespace {

// About a minute on two cores.
constexpr double kPreviewReferenceMaxWork = 4e9;

std::vector<double> brute_force(const EnvImage& env, const Vec3& view, const std::vector<ReferencePixel>& pixels,
                                double subdivision, const std::function<void(double)>& progress, double done_before,
                                double total) {
  std::vector<double> out(9 * pixels.size(), 0.0);
  std::atomic<size_t> next{0}, done{0};
  std::mutex progress_mutex;
  auto worker = [&] {
    for (size_t i = next++; i < pixels.size() && !cancel_requested(); i = next++) {
      const ReferencePixel& p = pixels[i];
      reference::PreviewFilm film;
      film.thickness_nm = p.film_thickness;
      film.film.film_ior = p.film_ior;
      film.film.base_f0 = {p.film_base_f0[0], p.film_base_f0[1], p.film_base_f0[2]};
      const reference::PreviewIntegrals r =
          reference::preview_integrals(env.rgb.data(), env.width, env.height, {p.n[0], p.n[1], p.n[2]}, view, p.alpha,
                                       subdivision, p.sheen, p.film ? &film : nullptr);
      for (size_t k = 0; k < 3; ++k) {
        out[9 * i + k] = r.s1[k];
        out[9 * i + 3 + k] = r.s2[k];
        out[9 * i + 6 + k] = r.irr[k];
      }
      const size_t d = ++done;
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress((done_before + double(d)) / total);
      }
    }
  };
  const unsigned n = std::max(1u, std::min<unsigned>(std::thread::hardware_concurrency(), unsigned(pixels.size())));
  std::vector<std::thread> pool;
  for (unsigned k = 1; k < n; ++k) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  throw_if_cancelled();
  return out;
}

class ReferencePreview final : public PreviewKernel {
 public:
  ReferenceSums reference(const ReferenceTask& task, const std::function<void(double)>& progress) override {
    const EnvImage& env = *task.environment;
    double work = 0.0;
    for (const auto& p : task.pixels)
      work += reference::preview_integrals_work(env.width, env.height, p.alpha, 16.0, p.sheen);
    for (const auto& p : task.bound_pixels)
      work += reference::preview_integrals_work(env.width, env.height, p.alpha, 32.0, p.sheen);
    if (work > kPreviewReferenceMaxWork)
      throw Error("the reference backend's brute-force preview of " + std::to_string(task.pixels.size()) +
                  " pixels under a " + std::to_string(env.width) + "x" + std::to_string(env.height) +
                  " environment is " + std::to_string(static_cast<long long>(work)) +
                  " lobe evaluations, above its limit of 4e9: use an OpenCL device, or a smaller image or environment");
    ReferenceSums out;
    out.method =
        "brute force over every pixel of the equirect, sub-cells where the lobe or the horizon needs them "
        "(host/reference/src/preview.cpp, scalar double)";
    const double total = double(task.pixels.size() + task.bound_pixels.size());
    const auto t0 = std::chrono::steady_clock::now();
    out.values = brute_force(env, task.view, task.pixels, 16.0, progress, 0.0, total);
    out.wall_seconds = out.device_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.cells.assign(task.pixels.size(), 0);
    const auto t1 = std::chrono::steady_clock::now();
    out.bound_values =
        brute_force(env, task.view, task.bound_pixels, 32.0, progress, double(task.pixels.size()), total);
    out.bound_wall_seconds = out.bound_device_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    return out;
  }
};

}  // namespace

std::unique_ptr<PreviewKernel> make_reference_preview() { return std::make_unique<ReferencePreview>(); }

}  // namespace brdfbake::detail
