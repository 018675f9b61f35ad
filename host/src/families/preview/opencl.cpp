// The reference render on an OpenCL device (kernels/preview.cl): the environment's quadtree built
// on the host (tree.cpp), one work-item a pixel.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "brdfbake/error.hpp"
#include "families/preview/kernel.hpp"
#include "families/preview/tree.hpp"
#include "runtime/launch.hpp"
#include "runtime/program.hpp"

namespace brdfbake::detail {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A pixel's walk visits a few thousand cells (a unit of launch_in_parts is one cell).
constexpr double kCellsPerPixel = 4000.0;
constexpr size_t kGroup = 32;  // pixels a work-group

// Whether a list of pixels holds a thin-film lobe.
bool has_film(const std::vector<ReferencePixel>& px) {
  return std::any_of(px.begin(), px.end(), [](const ReferencePixel& p) { return p.film; });
}

// The reference kernel (kernels/preview.cl) at the task's precision.
cl::Program reference_program(Device::Impl& dev, const ReferenceTask& task) {
  ProgramSpec ps;
  ps.file = "preview.cl";
  ps.precision = task.precision;
  // The thin-film lobe is compiled in only when a pixel has it (the default grid's program stays
  // as it is: glTF materials decide which lobes the kernel is built with).
  if (has_film(task.pixels) || has_film(task.bound_pixels)) ps.defines.push_back({"PREVIEW_IRIDESCENCE", "1"});
  return build_program(dev, ps);
}

// The kernel's pixel records: 8 floats a pixel (n, alpha, albedo, bias, the lobe) and, when a pixel
// has a film, 8 floats a pixel of its thickness, index and base F0 (else one: OpenCL has no empty buffers).
void pack_pixels(const std::vector<ReferencePixel>& pixels, std::vector<float>& px, std::vector<float>& film) {
  px.assign(8 * pixels.size(), 0.0f);
  film.assign(has_film(pixels) ? 8 * pixels.size() : 1, 0.0f);
  for (size_t i = 0; i < pixels.size(); ++i) {
    const ReferencePixel& p = pixels[i];
    float* d = &px[8 * i];
    d[0] = p.n[0];
    d[1] = p.n[1];
    d[2] = p.n[2];
    d[3] = p.alpha;
    d[4] = p.albedo;
    d[5] = p.bias;
    d[6] = p.film ? 2.0f : p.sheen ? 1.0f : 0.0f;
    if (p.film) {
      float* f = &film[8 * i];
      f[0] = p.film_thickness;
      f[1] = p.film_ior;
      std::copy(p.film_base_f0, p.film_base_f0 + 3, f + 2);
    }
  }
}

// The environment's quadtree, its image and its bright pixels on the device.
struct TreeBuffers {
  cl::Buffer tree, image, level, bright_index, bright_rgb;
  cl_int n_bright = 0;
};

TreeBuffers upload_tree(Device::Impl& dev, const preview::EnvTree& tree) {
  TreeBuffers b;
  b.tree = cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, tree.data.size() * sizeof(float),
                      const_cast<float*>(tree.data.data()));
  b.image = cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, tree.image.size() * sizeof(float),
                       const_cast<float*>(tree.image.data()));
  std::vector<cl_int4> levels;
  for (const auto& l : tree.levels) levels.push_back({{l[0], l[1], l[2], l[3]}});
  b.level =
      cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, levels.size() * sizeof(cl_int4), levels.data());
  // the bright pixels (at least one element each: OpenCL has no empty buffers)
  std::vector<cl_int> bright_index(tree.bright_index.begin(), tree.bright_index.end());
  std::vector<float> bright_rgb = tree.bright_rgb;
  b.n_bright = static_cast<cl_int>(bright_index.size());
  bright_index.resize(std::max<size_t>(1, bright_index.size()), 0);
  bright_rgb.resize(std::max<size_t>(3, bright_rgb.size()), 0.0f);
  b.bright_index = cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              bright_index.size() * sizeof(cl_int), bright_index.data());
  b.bright_rgb = cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bright_rgb.size() * sizeof(float),
                            bright_rgb.data());
  return b;
}

// A pass's results: 12 reals a pixel, as doubles.
std::vector<double> read_results(Device::Impl& dev, const cl::Buffer& out_buf, size_t n_pixels, bool fp64) {
  std::vector<double> raw(12 * n_pixels);
  if (fp64) {
    dev.queue.enqueueReadBuffer(out_buf, CL_TRUE, 0, raw.size() * sizeof(double), raw.data());
  } else {
    std::vector<float> f(raw.size());
    dev.queue.enqueueReadBuffer(out_buf, CL_TRUE, 0, f.size() * sizeof(float), f.data());
    std::copy(f.begin(), f.end(), raw.begin());
  }
  return raw;
}

class OpenClPreview final : public PreviewKernel {
 public:
  explicit OpenClPreview(Device& device) : device_(device) {}

  ReferenceSums reference(const ReferenceTask& task, const std::function<void(double)>& progress) override {
    Device::Impl& dev = device_.impl();
    ReferenceSums out;
    out.method = "quadtree walk of the equirect's constant cells (kernels/preview.cl) on '" + dev.info.name + "'";
    const auto t0 = Clock::now();
    const preview::EnvTree tree = preview::build_env_tree(*task.environment);
    cl::Program program = reference_program(dev, task);
    const bool fp64 = task.precision == Precision::Fp64;
    const size_t real_size = fp64 ? sizeof(double) : sizeof(float);
    const std::string what = "kernel preview_reference on '" + dev.info.name + "'";
    const double tree_bytes = double(tree.data.size()) * sizeof(float);
    const double image_bytes = double(tree.image.size()) * sizeof(float);
    const size_t n_all = std::max(task.pixels.size(), task.bound_pixels.size());
    check_device_memory(dev, tree_bytes, tree_bytes + image_bytes + double(n_all) * (64.0 + 12.0 * double(real_size)),
                        "the environment's quadtree (" + std::to_string(tree.image_width) + "x" +
                            std::to_string(tree.image_height) + ")");
    const double total = double(task.pixels.size() + task.bound_pixels.size());
    cl_call(what, [&] {
      const TreeBuffers buffers = upload_tree(dev, tree);
      cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl_int, cl_int,
                        cl_int, cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl::Buffer>
          walk(program, "preview_reference");
      // One pass over a list of pixels at a refinement; done_before: pixels of the earlier pass.
      auto pass = [&](const std::vector<ReferencePixel>& pixels, double refinement, double done_before,
                      std::vector<double>& values, std::vector<int>* cells, size_t* overflows) {
        values.assign(9 * pixels.size(), 0.0);
        if (pixels.empty()) return 0.0;
        std::vector<float> px, film;
        pack_pixels(pixels, px, film);
        cl::Buffer film_buf(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, film.size() * sizeof(float),
                            film.data());
        const PreviewRulesValues rules = preview_rules(refinement, task.radiance_scale);
        const std::vector<double> params = {task.view.x,        task.view.y,          task.view.z,    refinement,
                                            rules.horizon_size, rules.horizon_energy, rules.max_size, 0.0};
        cl::Buffer px_buf(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, px.size() * sizeof(float), px.data());
        std::vector<float> params_f(params.begin(), params.end());
        cl::Buffer param_buf = fp64 ? cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                                 params.size() * sizeof(double), const_cast<double*>(params.data()))
                                    : cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                                 params_f.size() * sizeof(float), params_f.data());
        cl::Buffer out_buf(dev.context, CL_MEM_WRITE_ONLY, 12 * pixels.size() * real_size);
        const cl_int n = static_cast<cl_int>(pixels.size());
        // Work-groups of kGroup pixels in every launch (PoCL compiles a kernel per work-group size:
        // launches of varying sizes would each compile it again): the launches cover groups, the last
        // one past the end, where the kernel returns at once.
        const size_t groups = (pixels.size() + kGroup - 1) / kGroup;
        const double seconds = launch_in_parts(
            // the cells a pixel's walk visits grow with the refinement's square (every threshold is
            // an angle / refinement over a 2D domain): the first launch of a high refinement then stays
            // short too, and a stop (DELETE, a timeout, SIGTERM) waits for a launch or two
            groups, kCellsPerPixel * std::max(1.0, (refinement / 4.0) * (refinement / 4.0)) * double(kGroup),
            [&](size_t first, size_t count) {
              return walk(cl::EnqueueArgs(dev.queue, cl::NDRange(first * kGroup), cl::NDRange(count * kGroup),
                                          cl::NDRange(kGroup)),
                          out_buf, px_buf, n, param_buf, buffers.tree, buffers.level, tree.start, tree.top,
                          tree.image_width, tree.image_height, buffers.image, buffers.bright_index, buffers.bright_rgb,
                          buffers.n_bright, film_buf);
            },
            [&](double f) {
              if (progress) progress((done_before + f * double(pixels.size())) / total);
            },
            std::min<size_t>(8, groups));
        const std::vector<double> raw = read_results(dev, out_buf, pixels.size(), fp64);
        for (size_t i = 0; i < pixels.size(); ++i) {
          std::copy(&raw[12 * i], &raw[12 * i] + 9, &values[9 * i]);
          if (cells) cells->push_back(int(raw[12 * i + 9]));
          if (overflows && raw[12 * i + 10] != 0.0) ++*overflows;
        }
        return seconds;
      };
      out.device_seconds = pass(task.pixels, task.refinement, 0.0, out.values, &out.cells, &out.overflows);
      out.wall_seconds = since(t0);
      const auto t1 = Clock::now();
      size_t bound_overflows = 0;
      out.bound_device_seconds = pass(task.bound_pixels, 2.0 * task.refinement, double(task.pixels.size()),
                                      out.bound_values, nullptr, &bound_overflows);
      out.bound_wall_seconds = since(t1);
      return 0;
    });
    return out;
  }

 private:
  Device& device_;
};

}  // namespace

std::unique_ptr<PreviewKernel> make_opencl_preview(Device& device) { return std::make_unique<OpenClPreview>(device); }

}  // namespace brdfbake::detail
