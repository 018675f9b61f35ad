// The chain's error bound with the reference's values summed on the device (kernels/prefilter_bound.cl):
// the same definition as the scalar reference (host/reference/src/prefilter.cpp, prefilter_directions),
// every sub-cell of level 0 against every sample direction in double, so the bound a chain records
// does not depend on where its reference was summed (tests/device/test_prefilter_bound.cpp holds the
// two to each other). The kernel classes of ChainBoundKernel (bound_kernel.hpp): OpenCL (this device
// in fp64, else the host's reference) and the reference backend's.
//
// What the device is given: level 0 in place (its float texels, CL_MEM_USE_HOST_PTR: no copy on a
// CPU device, none in double anywhere), the sample directions of every level that shares a
// subdivision q, BRDFBAKE_LANES a block and at most 8 blocks a launch (sorted by face and position,
// so that a block's lanes look the same way and a row's culled part is large), each lane's alpha,
// and the antiderivative F of the face's solid angle at the (size q + 1)^2 sub-cell corners
// (computed here in double as math::cube_rect_solid_angle computes it: the solid angles are the
// reference's to the last bit) where that table is no larger than level 0 itself; past that (small
// sources' fine sub-cells) the kernel computes F along each row itself. It answers per row of
// sub-cells and lane the four sums, which are added here row by row.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "env/cube.hpp"
#include "families/kernels.hpp"
#include "families/prefilter/bound_kernel.hpp"
#include "runtime/launch.hpp"

namespace brdfbake::detail {

namespace {

constexpr int kLanes = kEnvVectorWidth;  // BRDFBAKE_LANES of prefilter_bound.cl
constexpr int kBlocks = 8;               // BOUND_BLOCKS of prefilter_bound.cl: blocks a launch

// F(a_i, b_j) = atan2(a b, sqrt(1 + a^2 + b^2)) at a_i = -1 + 2 i / n, b_j likewise, j (n + 1) + i
// (F is symmetric in a and b, and a_k = b_k: half of it computed).
std::vector<double> solid_angle_corners(int n) {
  const size_t m = size_t(n) + 1;
  std::vector<double> f(m * m);
  for (size_t j = 0; j < m; ++j) {
    const double b = -1.0 + 2.0 * double(j) / n;
    for (size_t i = 0; i <= j; ++i) {
      const double a = -1.0 + 2.0 * double(i) / n;
      f[j * m + i] = f[i * m + j] = std::atan2(a * b, std::sqrt(1.0 + a * a + b * b));
    }
  }
  return f;
}

// One direction of a sample: which sample and which of its directions, and its face position (the
// blocks' order).
struct Lane {
  size_t sample, index;
  int face;
  double a, b;
};

// One launch's directions, at most kBlocks x kLanes (a chunk of a group's sorted lanes), against
// every row of sub-cells: their reference values into `out`. Returns the device seconds.
double run_chunk(Device::Impl& dev, const cl::Program& prog, const CubeLevels& cube, const cl::Buffer& level0,
                 const cl::Buffer& corner_buf, bool table, int q, const std::vector<BoundLevelSample>& samples,
                 const Lane* lanes, size_t count, std::vector<std::vector<double>>& out) {
  const int blocks = static_cast<int>((count + kLanes - 1) / kLanes);
  std::vector<double> dirs(size_t(blocks) * 4 * kLanes);
  for (int bl = 0; bl < blocks; ++bl)
    for (int k = 0; k < kLanes; ++k) {
      // padding lanes repeat the block's first direction: their sums are not read
      const size_t t = size_t(bl) * kLanes + size_t(k);
      const Lane& l = lanes[t < count ? t : size_t(bl) * kLanes];
      const Vec3& d = samples[l.sample].directions[l.index];
      const double r = samples[l.sample].roughness;
      double* o = &dirs[size_t(bl) * 4 * kLanes];
      o[k] = d.x;
      o[kLanes + k] = d.y;
      o[2 * kLanes + k] = d.z;
      o[3 * kLanes + k] = std::max(r * r, math::kMinAlpha);  // floor_alpha of the reference's alpha
    }
  const int n = cube.size * q;
  const size_t rows = 6u * size_t(n);
  const size_t partial_doubles = rows * size_t(blocks) * 4 * kLanes;
  check_allocation(dev, partial_doubles * sizeof(double), "the chain bound's partial sums");
  std::vector<double> partial(partial_doubles, 0.0);
  cl::Buffer dirs_buf(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, dirs.size() * sizeof(double), dirs.data());
  cl::Buffer out_buf(dev.context, CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR, partial.size() * sizeof(double),
                     partial.data());
  cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl_int, cl::Buffer, cl_int, cl::Buffer, cl_int> kernel(
      prog, "prefilter_bound_reference");
  // rows in parts of about 50 ms (runtime/launch.hpp), one work-item a row, in a fixed work-group:
  // of one in the CPU shape (PoCL compiles a kernel once per work-group size), of 32 rows in the GPU
  // shape (docs/DEVICES.md: a warp's work-items on neighbouring rows; the launches cover whole
  // groups, the last past the end, where the kernel returns at once); a row's cost: its sub-cells x
  // the lanes
  const size_t group =
      dev.info.kernel_shape == "gpu" ? std::min<size_t>(32, std::max<size_t>(1, dev.info.max_work_group_size)) : 1;
  const size_t groups = (rows + group - 1) / group;
  const double seconds =
      launch_in_parts(groups, double(n) * blocks * kLanes * double(group), [&](size_t first, size_t n_groups) {
        return kernel(
            cl::EnqueueArgs(dev.queue, cl::NDRange(first * group), cl::NDRange(n_groups * group), cl::NDRange(group)),
            out_buf, level0, cube.size, q, corner_buf, table ? 1 : 0, dirs_buf, blocks);
      });
  void* mapped = dev.queue.enqueueMapBuffer(out_buf, CL_TRUE, CL_MAP_READ, 0, partial.size() * sizeof(double));
  dev.queue.enqueueUnmapMemObject(out_buf, mapped);
  dev.queue.finish();
  // every lane's sums, row by row in order; P = num / den as the reference divides
  for (size_t t = 0; t < count; ++t) {
    const size_t bl = t / kLanes, k = t % kLanes;
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    for (size_t row = 0; row < rows; ++row) {
      const double* p = &partial[(row * size_t(blocks) + bl) * 4 * kLanes];
      for (size_t c = 0; c < 4; ++c) sum[c] += p[c * kLanes + k];
    }
    double* o = &out[lanes[t].sample][3 * lanes[t].index];
    for (size_t c = 0; c < 3; ++c) o[c] = sum[3] > 0.0 ? sum[c] / sum[3] : 0.0;
  }
  return seconds;
}

// The samples `which` (all of one subdivision q) on the device: their reference values into `out`.
double run_group(Device::Impl& dev, const cl::Program& prog, const CubeLevels& cube, const cl::Buffer& level0,
                 const std::vector<BoundLevelSample>& samples, const std::vector<size_t>& which, int q,
                 std::vector<std::vector<double>>& out) {
  std::vector<Lane> lanes;
  for (size_t s : which)
    for (size_t k = 0; k < samples[s].directions.size(); ++k) {
      Lane l{s, k, 0, 0.0, 0.0};
      math::cube_face_coords(samples[s].directions[k], l.face, l.a, l.b);
      lanes.push_back(l);
    }
  if (lanes.empty()) return 0.0;
  // by face, then in bands of rows, then along them: a block's lanes look the same way
  std::sort(lanes.begin(), lanes.end(), [](const Lane& x, const Lane& y) {
    const int bx = int(std::floor((x.b + 1.0) * 2.0)), by = int(std::floor((y.b + 1.0) * 2.0));
    if (x.face != y.face) return x.face < y.face;
    if (bx != by) return bx < by;
    return x.a < y.a;
  });
  const int n = cube.size * q;
  // the corners' table where it is no larger than level 0 (one element, unread, where it is not)
  const size_t corner_bytes = (size_t(n) + 1) * (size_t(n) + 1) * sizeof(double);
  const bool table = corner_bytes <= cube.levels[0].size() * sizeof(float);
  std::vector<double> corners = table ? solid_angle_corners(n) : std::vector<double>(1, 0.0);
  cl::Buffer corner_buf(dev.context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, corners.size() * sizeof(double),
                        corners.data());
  double seconds = 0.0;
  const size_t per_launch = size_t(kBlocks) * kLanes;
  for (size_t first = 0; first < lanes.size(); first += per_launch)
    seconds += run_chunk(dev, prog, cube, level0, corner_buf, table, q, samples, &lanes[first],
                         std::min(per_launch, lanes.size() - first), out);
  return seconds;
}

}  // namespace

std::vector<std::vector<double>> device_bound_reference(Device& device, const CubeLevels& cube,
                                                        EnvDistribution distribution,
                                                        const std::vector<BoundLevelSample>& samples,
                                                        double* device_seconds) {
  Device::Impl& dev = device.impl();
  if (!dev.info.fp64)
    throw Error("the chain bound's reference on the device needs fp64, which '" + dev.info.name + "' has not");
  std::vector<std::vector<double>> out(samples.size());
  for (size_t s = 0; s < samples.size(); ++s) out[s].assign(3 * samples[s].directions.size(), 0.0);
  // the mirror (roughness 0) is the environment itself: the host's reference reads it
  std::vector<BoundLevelSample> mirror;
  std::vector<size_t> mirror_at;
  std::vector<int> qs;
  for (size_t s = 0; s < samples.size(); ++s) {
    if (samples[s].roughness == 0.0) {
      mirror.push_back(samples[s]);
      mirror_at.push_back(s);
    } else if (std::find(qs.begin(), qs.end(), samples[s].subdivision) == qs.end()) {
      qs.push_back(samples[s].subdivision);
    }
  }
  if (!mirror.empty()) {
    const std::vector<std::vector<double>> m = host_bound_reference(cube, distribution, mirror);
    for (size_t k = 0; k < mirror.size(); ++k) out[mirror_at[k]] = m[k];
  }
  if (qs.empty()) return out;
  const char* lobe_define = distribution == EnvDistribution::Charlie ? "BRDFBAKE_ENV_CHARLIE" : "BRDFBAKE_ENV_GGX";
  const cl::Program prog = env_program(dev, "prefilter_bound.cl", Precision::Fp64, {{lobe_define, "1"}});
  std::vector<float>& level = const_cast<std::vector<float>&>(cube.levels[0]);  // read only (CL_MEM_READ_ONLY)
  cl::Buffer level0(dev.context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, level.size() * sizeof(float), level.data());
  double seconds = 0.0;
  cl_call("measuring the chain's bound on '" + dev.info.name + "'", [&] {
    for (int q : qs) {
      std::vector<size_t> which;
      for (size_t s = 0; s < samples.size(); ++s)
        if (samples[s].roughness != 0.0 && samples[s].subdivision == q) which.push_back(s);
      seconds += run_group(dev, prog, cube, level0, samples, which, q, out);
    }
    return 0;
  });
  if (device_seconds) *device_seconds += seconds;
  return out;
}

namespace {

class OpenClChainBound final : public ChainBoundKernel {
 public:
  explicit OpenClChainBound(Device& device) : device_(device) {}
  ChainBound measure(const CubeLevels& cube, EnvDistribution distribution,
                     const std::vector<double>& roughness) override {
    // the host's reference where the device has no fp64, or cannot hold level 0 in one buffer
    const DeviceInfo& info = device_.impl().info;
    const size_t level0_bytes = cube.levels.empty() ? 0 : cube.levels[0].size() * sizeof(float);
    if (!info.fp64 || (info.max_alloc != 0 && level0_bytes > info.max_alloc))
      return chain_error_bound(cube, distribution, roughness);
    double device_seconds = 0.0;
    ChainBound b =
        chain_error_bound(cube, distribution, roughness,
                          [&](const CubeLevels& c, EnvDistribution d, const std::vector<BoundLevelSample>& samples) {
                            return device_bound_reference(device_, c, d, samples, &device_seconds);
                          });
    b.on_device = true;
    b.device_seconds = device_seconds;
    return b;
  }

 private:
  Device& device_;
};

class ReferenceChainBound final : public ChainBoundKernel {
 public:
  ChainBound measure(const CubeLevels& cube, EnvDistribution distribution,
                     const std::vector<double>& roughness) override {
    return chain_error_bound(cube, distribution, roughness);
  }
};

}  // namespace

std::unique_ptr<ChainBoundKernel> make_opencl_chain_bound(Device& device) {
  return std::make_unique<OpenClChainBound>(device);
}

std::unique_ptr<ChainBoundKernel> make_reference_chain_bound() { return std::make_unique<ReferenceChainBound>(); }

ChainBound chain_error_bound(Backend& backend, const CubeLevels& cube, EnvDistribution distribution,
                             const std::vector<double>& roughness) {
  return run_kernel<ChainBoundKernel>(backend,
                                      [&](ChainBoundKernel& k) { return k.measure(cube, distribution, roughness); });
}

}  // namespace brdfbake::detail
