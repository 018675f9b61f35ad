// The DFG tables on the reference backend: bake_lut_reference, every texel a converged integral of
// the scalar double reference (host/reference/src/dfg_lut.cpp), and the family's reference kernel.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "brdfbake/cancel.hpp"
#include "brdfbake/reference/dfg_lut.hpp"
#include "families/dfg_lut/kernel.hpp"
#include "families/dfg_lut/model.hpp"

namespace brdfbake {
namespace {

reference::SheenVisibility to_reference(SheenVisibility v) {
  return v == SheenVisibility::Neubelt ? reference::SheenVisibility::Neubelt : reference::SheenVisibility::EstevezKulla;
}

// The reference values of one texel, channels in lut_channels order.
void reference_texel(LutKind kind, double n_dot_v, double roughness, reference::SheenVisibility vis, float* out) {
  if (kind == LutKind::Charlie) {
    out[0] = static_cast<float>(reference::charlie_albedo(n_dot_v, roughness, vis));
    return;
  }
  const auto d = reference::dfg_ggx(n_dot_v, roughness);
  out[0] = static_cast<float>(kind == LutKind::Ggx ? d.scale : d.bias);
  out[1] = static_cast<float>(kind == LutKind::Ggx ? d.bias : d.scale + d.bias);
  out[2] = static_cast<float>(reference::burley_albedo(n_dot_v, roughness));
}

class ReferenceDfgLut final : public detail::DfgLutKernel {
 public:
  Table bake(const LutSpec& spec, LutTiming* timing, const Progress& progress) override {
    return bake_lut_reference(spec, timing, progress);
  }
};

}  // namespace

std::unique_ptr<detail::DfgLutKernel> detail::make_reference_dfg_lut() { return std::make_unique<ReferenceDfgLut>(); }

Table bake_lut_reference(const LutSpec& in, LutTiming* timing, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  LutSpec s = resolve_lut_spec(in);
  Table t = detail::make_lut_table(s);
  const auto vis = to_reference(s.sheen_visibility);
  // Rows are shared among the cores; each texel is an independent converged integral.
  std::atomic<int> next_row{0}, done_rows{0};
  std::mutex progress_mutex;
  auto worker = [&] {
    for (int j = next_row++; j < s.height && !cancel_requested(); j = next_row++) {
      for (int i = 0; i < s.width; ++i)
        reference_texel(s.kind, s.n_dot_v[size_t(i)], s.roughness[size_t(j)], vis, &t.at(i, j, 0));
      const int done = ++done_rows;
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress(static_cast<double>(done) / s.height);
      }
    }
  };
  const unsigned n_threads =
      std::max(1u, std::min(std::thread::hardware_concurrency(), static_cast<unsigned>(s.height)));
  std::vector<std::thread> pool;
  for (unsigned k = 1; k < n_threads; ++k) pool.emplace_back(worker);
  // The calling thread works too, and its progress reports may throw (a run's stop: the server's
  // abandoned request): the others stop at their next row and are joined before it propagates.
  std::exception_ptr stopped;
  try {
    worker();
  } catch (...) {
    stopped = std::current_exception();
    next_row = s.height;
  }
  for (auto& th : pool) th.join();
  if (stopped) std::rethrow_exception(stopped);
  throw_if_cancelled();  // the workers stop at the next row (they may not throw themselves)
  t.set_meta("device", "reference (scalar double, converged quadrature)");
  t.set_meta("precision", "fp64");
  t.set_meta("estimator", "reference");
  t.set_meta("samples", "converged");
  t.set_meta("error_bound", "1e-06");  // kLutReferenceBound
  t.set_meta("error_bound_definition", "the reference's stated convergence (tests/reference)");
  if (timing) {
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timing->device_seconds = timing->wall_seconds;
  }
  return t;
}

}  // namespace brdfbake
