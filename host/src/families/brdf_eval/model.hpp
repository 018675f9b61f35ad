// Internal: the BRDF evaluation engine's model, what the eval and tabulate families' files share:
// names (names.cpp), the materials' parameter blocks (material.cpp), programs and buffers
// (evaluator.cpp), tables and their metadata (tabulate.cpp), and what the reference adapter
// (reference.cpp) needs of them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/cancel.hpp"
#include "brdfbake/table.hpp"
#include "enum_names.hpp"
#include "runtime/program.hpp"

namespace brdfbake::detail {

// The tabulate layouts' names (names.cpp's table_layout_from_name and table_layout_name; the schema offers them).
inline constexpr EnumName<TableLayout> kTableLayoutNames[] = {{TableLayout::Merl, "merl"},
                                                              {TableLayout::Grid, "grid"},
                                                              {TableLayout::Albedo, "albedo"},
                                                              {TableLayout::Slice, "slice"}};

inline double max3(const Rgb& c) { return std::max(c.r, std::max(c.g, c.b)); }
inline double mix(double a, double b, double t) { return a + (b - a) * t; }
inline bool is_gltf(BrdfModel m) { return m == BrdfModel::Gltf || m == BrdfModel::GltfCorrelated; }
// The model's compile-time switch of kernels/brdf_eval.cl.
const char* brdf_model_define(BrdfModel model);

// The parameter blocks (BRDF_PARAM_STRIDE per material) and sheen tables (the E(mu) pieces of each
// distinct sheen roughness) of a set of materials.
struct PackedMaterials {
  std::vector<double> params;
  std::vector<double> sheen;
};
PackedMaterials pack_materials(BrdfModel model, const std::vector<Material>& materials);
// The narrowest lobe of a material, in radians of the half vector's polar angle: the albedo
// quadrature starts its log-spaced polar nodes 1e-4 of it below it.
double narrowest_lobe(BrdfModel model, const Material& material);

// The program of a model for the lobes used, in the options' precision, `lanes` directions a
// work-item; the lane count of the options (8 or 16; 0 the measured best).
ProgramSpec brdf_program_spec(BrdfModel model, const Lobes& lobes, const EvalOptions& options, int lanes);
// The lanes of a program: options.lanes, else the device's kernel shape's (DeviceInfo::kernel_shape):
// cpu 16 in fp32 and 8 in fp64 (bench/brdf_bench on PoCL), gpu 4 (a work-item is one lane of a warp:
// float16 vectors spill its registers, and fp64 outran fp32 on an H200 for that reason).
int resolve_lanes(const EvalOptions& options, const DeviceInfo& device);
// Pairs a batch on a GPU-shaped device, per compute unit: 16,384 x 132 SMs = 2.2M pairs a launch on
// an H200, where 2M measured 15.4 G evaluations/s against 1.67 at 65,536 (docs/BENCHMARKS.md).
inline constexpr size_t kGpuPairsPerComputeUnit = size_t(1) << 14;
size_t eval_chunk_pairs(const DeviceInfo& device);
// Device-side copies of a real-valued host array in the program's precision, and back.
cl::Buffer brdf_real_buffer(Device::Impl& dev, Precision p, const std::vector<double>& v,
                            cl_mem_flags flags = CL_MEM_READ_ONLY);
size_t real_size(Precision p);
void read_reals(Device::Impl& dev, Precision p, const cl::Buffer& buffer, size_t n, double* out);

// "direction pair i: <which> is zero or not finite".
std::string pair_error(std::size_t i, const char* which);
// Normalises a direction in double (largest component divided out first); false when it is zero or
// not finite.
bool unit_direction(const double* v, double* out);

// Throws Error for a spec the tabulation rejects (no materials, too many for the layout, a material
// out of range, a slice angle outside [0, pi]).
void check_tabulate_spec(const TabulateSpec& spec);
// The grid, albedo or slice table of a checked spec at a resolved resolution: axes and the layout's
// metadata, data zero.
Table make_tabulate_table(const TabulateSpec& spec, const std::vector<int>& resolution);
// The metadata every table records (model, materials, layout, resolution, precision, device, lobes,
// conventions, generator); set or replaced in `meta`.
void tabulate_metadata(Metadata& meta, const TabulateSpec& spec, const std::vector<int>& resolution,
                       const std::string& device, const std::string& precision, const std::string& lobes);
// The merl layout's description.
void merl_metadata(Metadata& meta);

// Runs body(k) for k in [0, n) on every core.
template <class Body>
void parallel_for(size_t n, Body&& body) {
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    try {
      for (size_t k = next++; k < n; k = next++) {
        throw_if_cancelled();  // caught below and rethrown on the calling thread
        body(k);
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      next = n;
    }
  };
  const unsigned threads =
      std::max(1u, std::min(std::thread::hardware_concurrency(), static_cast<unsigned>(std::max<size_t>(1, n))));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace brdfbake::detail
