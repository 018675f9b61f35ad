// The prefiltered radiance mip chain on the device (kernels/cubemap.cl, kernels/prefilter.cl).
//
// Steps (docs/CONVENTIONS.md, "Environment maps", says what each level holds):
//   1. the source cube is level 0, the mirror (roughness 0) (conversion: env/conversion.cpp);
//   2. environment sampling: the brightest texels of level 0 (find_bright_texels) are taken out into
//      an explicit list; the rest is read through the quadrature's pyramid (pyramid.cpp, built on the
//      host) or, for the sampling estimator, its padded mip chain down to 1x1 (env/device.cpp);
//   3. every output level l >= 1 is filtered by the estimator, plus the exact sum over the bright
//      texels (kernels/prefilter.cl derives the estimators); with max_error each level is searched:
//      successive refinements (or sample counts) until two agree within it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "env/cube.hpp"
#include "families/prefilter/launch.hpp"
#include "families/prefilter/lobes.hpp"
#include "families/prefilter/model.hpp"
#include "runtime/launch.hpp"
#include "text.hpp"

namespace brdfbake::detail {

namespace {

// RMS relative difference of two levels (luminance), the measured error estimate of --chain-max-error.
double rms_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t t = 0; t < a.size(); t += 4) {
    const double la = luminance(&a[t]), lb = luminance(&b[t]);
    const double d = std::fabs(la - lb) / std::max(std::fabs(lb), 1e-30);
    sum += d * d;
    ++count;
  }
  return std::sqrt(sum / double(std::max<size_t>(count, 1)));
}

// Progress: every level's fixed cost, as a share of the chain's estimated work.
constexpr double kProgressLevelOverhead = 0.05;

// What one level's launches read beside the source: the bright texels' points and the estimator's
// tables (the quadrature's thresholds, or the lobe samples).
struct LevelInputs {
  double alpha = 0.0;
  std::vector<double> pts;  // bright points (bright_texel_points' layout)
  int n_pts = 0;
  double scale = 1.0;  // what the points' L Omega was scaled by
  cl::Buffer pts_buf, core_buf, band_buf, table_buf;
  int n_padded = 0;  // sampling: lobe samples with padding
};

// One chain being made: the source (pyramid or padded chain), the program, and what every level
// records. bake() runs the levels.
class ChainBaker {
 public:
  ChainBaker(Device::Impl& dev, const PrefilterSpec& s, CubeLevels source,
             const std::vector<double>* roughness = nullptr)
      : dev_(dev),
        s_(s),
        levels_(prefilter_level_count(s)),
        s0_(s.size),
        quadrature_(s.estimator == EnvEstimator::Quadrature) {
    out_.size = s0_;
    out_.metadata = std::move(source.metadata);
    out_.levels.resize(size_t(levels_));
    out_.levels[0] = std::move(source.levels[0]);
    source.levels.clear();
    if (s.clamp_luminance > 0.0) clamp_luminance(out_.levels[0], s.clamp_luminance);
    // Environment sampling: the bright texels leave the rest.
    const int max_bright = s.bright_texels < 0 ? kDefaultBrightTexels : s.bright_texels;
    bright_ = find_bright_texels(out_, max_bright, kBrightRatio);
    stage("bright texels");
    const size_t n = size_t(levels_);
    rec_.roughness.assign(n, 0.0);
    rec_.seconds.assign(n, 0.0);
    rec_.refinement.assign(n, s.refinement);
    rec_.samples.assign(n, 0);
    rec_.measured.assign(n, 0.0);
    rec_.bright = bright_.size();
    for (int l = 0; l < levels_; ++l) {
      rec_.roughness[size_t(l)] =
          roughness && l > 0 ? (*roughness)[size_t(l)] : schedule_roughness(s.schedule, l, levels_);
      if (l > 0 && !quadrature_)
        rec_.samples[size_t(l)] = s.samples > 0 ? s.samples : default_prefilter_samples(l, levels_);
    }
  }

  // Every level (throws cl::Error from the device); returns the device seconds.
  double bake(const EnvProgress& report) {
    // forward only, whatever the rounding of the levels' shares
    double last = 0.0;
    EnvProgress progress;
    if (report)
      progress = [&](double f, const std::string& label) {
        last = std::max(last, std::min(f, 1.0));
        report(last, label);
      };
    filter_prog_ = filter_program(dev_, s_);
    stage("program");
    prepare_source();
    stage(quadrature_ ? "pyramid" : "source chain");
    // Progress by the work of each level, its texels times the evaluations of one (texel_work): a
    // texel of a rough Charlie level costs many times one of a sharp GGX level.
    std::vector<double> work(size_t(levels_), 0.0);
    double total_work = 0.0, done_work = 0.0;
    for (int l = 1; l < levels_; ++l) {
      work[size_t(l)] = double(face_texels(out_.level_size(l))) * texel_work(l);
      total_work += work[size_t(l)];
    }
    // Plus what every level costs whatever its texels (its launches, at least 4 with progress).
    const double overhead = kProgressLevelOverhead * total_work;
    for (int l = 1; l < levels_; ++l) work[size_t(l)] += overhead;
    total_work += overhead * (levels_ - 1);
    for (int l = 1; l < levels_; ++l) {
      device_seconds_ += bake_level(l, progress, total_work, done_work, work[size_t(l)]);
      done_work += work[size_t(l)];
      stage("level " + std::to_string(l));
    }
    if (progress) progress(1.0, "done");
    return device_seconds_;
  }

  CubeLevels& out() { return out_; }
  const ChainRecord& record() const { return rec_; }

 private:
  void stage(std::string name) {
    const auto now = std::chrono::steady_clock::now();
    rec_.stages.emplace_back(std::move(name), std::chrono::duration<double>(now - stage_mark_).count());
    stage_mark_ = now;
  }

  double alpha_of(int l) const {
    return std::max(rec_.roughness[size_t(l)] * rec_.roughness[size_t(l)], math::kMinAlpha);
  }

  // The source: the quadrature's pyramid (built here, on the host, in double), or the sampling
  // estimator's padded mip chain (built on the device).
  void prepare_source() {
    if (quadrature_) {
      std::vector<double> alphas;
      for (int l = 1; l < levels_; ++l) alphas.push_back(alpha_of(l));
      std::vector<uint8_t> skip;
      if (!bright_.empty()) {
        skip.assign(face_texels(s0_), 0);
        for (const BrightTexel& b : bright_)
          skip[(size_t(b.face) * size_t(s0_) + size_t(b.j)) * size_t(s0_) + size_t(b.i)] = 1;
      }
      pyramid_ = build_pyramid(out_.levels[0], s0_, pyramid_base_level(s0_, s_.distribution, alphas, s_), skip);
      check_allocation(dev_, pyramid_.data.size() * sizeof(float), "the quadrature's pyramid");
      // USE_HOST_PTR: a CPU device reads the host's copy (it outlives every level), a GPU uploads it
      pyramid_buf_ = cl::Buffer(dev_.context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR,
                                pyramid_.data.size() * sizeof(float), pyramid_.data.data());
      pyramid_info_ = cl::Buffer(dev_.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                 pyramid_.info.size() * sizeof(cl_int), pyramid_.info.data());
      return;
    }
    cl::Program cube_prog = env_program(dev_, "cubemap.cl", s_.precision);
    std::vector<cl::Event> chain_events;
    std::vector<float> rest = out_.levels[0];
    for (const BrightTexel& b : bright_) {
      float* t = &rest[4 * ((size_t(b.face) * size_t(s0_) + size_t(b.j)) * size_t(s0_) + size_t(b.i))];
      t[0] = t[1] = t[2] = 0.0f;
    }
    cl::Buffer level0(dev_.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, rest.size() * sizeof(float), rest.data());
    chain_ = build_padded_chain(dev_, cube_prog, level0, s0_, chain_events);
    for (auto& e : chain_events) e.wait();
    rec_.seconds[0] = sum_seconds(chain_events);
    device_seconds_ += rec_.seconds[0];
  }

  // The evaluations one texel of level l costs, for progress. Sampling: its lobe samples. The
  // quadrature: the walk visits the top level's texels, then at each level k >= 1 the children of
  // the texels it refines there (a core c > cos_core[k] or a band lo < c < hi of c = R.d), about
  // their share of the sphere (a cap is 2 pi (1 - c), a band 2 pi (hi - lo), of 4 pi) times the
  // texels of level k - 1; a block of 8 x 8 texels (strips) walks the union of its texels' regions
  // (each widened by the block's half diagonal) once, evaluating every visited texel for each of
  // its 64. Both: plus the bright texels' points.
  double texel_work(int l) const {
    const double alpha = alpha_of(l);
    const int q = std::min(bright_subdivision(s_.distribution, alpha, s0_, bright_.size()),
                           bright_lobe_subdivision(s_.distribution, alpha, s0_));
    const double bright = double(bright_.size()) * 4.0 * q * q;
    if (!quadrature_) return double(std::max(rec_.samples[size_t(l)], 1)) + bright;
    const int size = out_.level_size(l);
    const bool strips = quadrature_ && use_strips(size);
    const double widen = strips ? std::sqrt(2.0) * 8.0 / size : 0.0;  // radians, at a face's centre
    std::vector<double> cos_core, band;
    pyramid_thresholds(pyramid_, s_.distribution, alpha, s_, rec_.refinement[size_t(l)], cos_core, band);
    const auto texels = [&](int k) { return 6.0 * double(pyramid_.sizes[size_t(k)]) * pyramid_.sizes[size_t(k)]; };
    double w = texels(pyramid_.levels - 1);
    for (int k = 1; k < pyramid_.levels; ++k) {
      double share = 0.0;
      if (cos_core[size_t(k)] <= 1.0) {
        const double theta = std::acos(std::max(cos_core[size_t(k)], -1.0)) + widen;
        share += 0.5 * (1.0 - std::cos(std::min(theta, math::kPi)));
      }
      if (band[2 * size_t(k)] < band[2 * size_t(k) + 1]) {
        const double lo = std::max(band[2 * size_t(k)] - widen, -1.0);
        const double hi = std::min(band[2 * size_t(k) + 1] + widen, 1.0);
        share += 0.5 * (hi - lo);
      }
      w += std::min(share, 1.0) * texels(k - 1);
    }
    return w + bright;
  }

  // One level with progress: a single run, or with max_error the search. Returns its device seconds.
  double bake_level(int l, const EnvProgress& progress, double total_work, double done_work, double level_work) {
    const std::string label = "level " + std::to_string(l) + "/" + std::to_string(levels_ - 1);
    if (progress) progress(total_work > 0 ? done_work / total_work : 0.0, label);
    // Within the level's share of the work: run k of a search (refinement or sample count, each
    // dearer than the last) fills [1 - 2^-k, 1 - 2^-(k+1)) of it, so the line moves on and never back.
    const double share = total_work > 0 ? level_work / total_work : 0.0;
    const double start = total_work > 0 ? done_work / total_work : 0.0;
    int run = 0;
    std::string step_label = label;
    auto step = [&](double f) {
      if (!progress) return;
      const double a = 1.0 - std::ldexp(1.0, -run), b = 1.0 - std::ldexp(1.0, -(run + 1));
      progress(start + share * (s_.max_error > 0.0 ? a + (b - a) * f : f), step_label);
    };
    std::function<void(double)> stepper;
    if (progress) stepper = step;
    auto search_run = [&](int n, double r, std::vector<float>& dst) {
      step_label = label + (quadrature_ ? ", refinement " + detail::fmt_number(r, "%.6g")
                                        : ", " + std::to_string(n) + " samples");
      const double t = run_level(l, n, r, dst, stepper);
      ++run;
      return t;
    };
    double& sec = rec_.seconds[size_t(l)];
    if (s_.max_error > 0.0 && quadrature_)
      sec += search_refinement(l, search_run);
    else if (s_.max_error > 0.0)
      sec += search_samples(l, search_run);
    else
      sec = run_level(l, rec_.samples[size_t(l)], rec_.refinement[size_t(l)], out_.levels[size_t(l)], stepper);
    return sec;
  }

  using SearchRun = std::function<double(int n, double r, std::vector<float>& dst)>;

  // Refinement 2, 3, 4, 6, 8, 12, 16: each result is compared with the next; the first pair closer
  // than max_error keeps the finer result (its error is a fraction of the difference).
  double search_refinement(int l, const SearchRun& search_run) {
    static const double kSteps[] = {2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0};
    std::vector<float> a, b;
    double sec = search_run(0, kSteps[0], a);
    for (size_t k = 1; k < std::size(kSteps); ++k) {
      sec += search_run(0, kSteps[k], b);
      rec_.refinement[size_t(l)] = kSteps[k];
      rec_.measured[size_t(l)] = rms_difference(a, b);
      const bool done = rec_.measured[size_t(l)] <= s_.max_error;
      a.swap(b);
      if (done) break;
    }
    out_.levels[size_t(l)] = std::move(a);
    return sec;
  }

  // Sampling: the difference of n and 4n samples estimates the error of n; n doubles from
  // kPrefilterSearchStart until it is below max_error, and the 4n result is kept.
  double search_samples(int l, const SearchRun& search_run) {
    std::vector<float> a, b;
    int n = kPrefilterSearchStart;
    double sec = search_run(n, 0.0, a);
    for (;;) {
      sec += search_run(4 * n, 0.0, b);
      rec_.measured[size_t(l)] = rms_difference(a, b);
      if (rec_.measured[size_t(l)] <= s_.max_error || 4 * n >= kPrefilterSearchMax) {
        rec_.samples[size_t(l)] = 4 * n;
        out_.levels[size_t(l)] = std::move(b);
        break;
      }
      n *= 2;
      sec += search_run(n, 0.0, a);
    }
    return sec;
  }

  // The inputs of level l with n samples (sampling) or refinement r (quadrature). Bright points
  // carry L Omega; the sampling estimator divides them by W = int K dl here, the quadrature by its
  // own sum of K Omega in the kernel.
  LevelInputs level_inputs(int l, int n, double r) {
    LevelInputs in;
    in.alpha = alpha_of(l);
    in.scale = quadrature_ ? 1.0 : 1.0 / env_lobe_normalization(s_.distribution, in.alpha);
    int n_points = 0;
    in.pts = bright_texel_points(bright_, s0_, bright_subdivision(s_.distribution, in.alpha, s0_, bright_.size()),
                                 in.scale, &n_points);
    in.n_pts = n_points > 0 ? static_cast<int>(in.pts.size() / 6) : 0;
    in.pts_buf = env_real_buffer(dev_, s_.precision, in.pts);
    if (quadrature_) {
      std::vector<double> cos_core, band;
      pyramid_thresholds(pyramid_, s_.distribution, in.alpha, s_, r, cos_core, band);
      in.core_buf = env_real_buffer(dev_, s_.precision, cos_core);
      in.band_buf = env_real_buffer(dev_, s_.precision, band);
    } else {
      int n_kept = 0;
      const std::vector<double> table =
          lobe_samples(s_.distribution, in.alpha, n, s0_, s_.filtered_importance_sampling, s_.lod_bias, &n_kept);
      in.table_buf = env_real_buffer(dev_, s_.precision, table);
      in.n_padded = static_cast<int>(table.size() / 5);
    }
    return in;
  }

  // The bright texels as the strips kernel reads them at a level of face `size`.
  StripBright strip_bright(const LevelInputs& in) {
    const double alpha = in.alpha;
    const int q_fine = bright_subdivision(s_.distribution, alpha, s0_, bright_.size());
    const int q_coarse = std::min(q_fine, bright_lobe_subdivision(s_.distribution, alpha, s0_));
    StripBright sb;
    sb.fine = in.pts_buf;
    sb.fine_stride = static_cast<int>(in.pts.size() / 6);
    sb.fine_per = 4 * q_fine * q_fine;
    sb.coarse_per = 4 * q_coarse * q_coarse;
    if (bright_single_point(s_.distribution, alpha, s0_) && !bright_.empty()) {
      // one point a texel: the merged coarse (or fine) points
      const bool from_fine = q_coarse == q_fine;
      int n_coarse = 0;
      const std::vector<double> cp =
          from_fine ? std::vector<double>{} : bright_texel_points(bright_, s0_, q_coarse, in.scale, &n_coarse);
      const std::vector<double>& src = from_fine ? in.pts : cp;
      const std::vector<double> merged =
          merge_bright_points(src, src.size() / 6, size_t(4 * q_coarse * q_coarse), bright_.size());
      sb.coarse = env_real_buffer(dev_, s_.precision, merged);
      sb.coarse_stride = static_cast<int>(merged.size() / 6);
      sb.coarse_per = 1;
    } else if (q_coarse == q_fine) {
      sb.coarse = in.pts_buf;
      sb.coarse_stride = sb.fine_stride;
    } else {
      int n_coarse = 0;
      const std::vector<double> coarse = bright_texel_points(bright_, s0_, q_coarse, in.scale, &n_coarse);
      sb.coarse = env_real_buffer(dev_, s_.precision, coarse);
      sb.coarse_stride = static_cast<int>(coarse.size() / 6);
    }
    std::vector<double> dirs(3 * std::max<size_t>(bright_.size(), 1), 0.0);
    for (size_t t = 0; t < bright_.size(); ++t) {
      const Vec3 d = math::cube_texel_direction(bright_[t].face, s0_, bright_[t].i, bright_[t].j);
      dirs[t] = d.x;
      dirs[bright_.size() + t] = d.y;
      dirs[2 * bright_.size() + t] = d.z;
    }
    sb.dirs = env_real_buffer(dev_, s_.precision, dirs);
    sb.texels = in.n_pts > 0 ? static_cast<int>(bright_.size()) : 0;
    // the tent's support reaches a texel diagonal (2 / s0 in face coordinates, at most as many
    // radians) from the centre; one more texel as margin
    sb.reach = (std::sqrt(2.0) + 1.0) * 2.0 / double(s0_);
    return sb;
  }

  // One level into `dst` with n samples (sampling) or refinement r (quadrature); waits, returns
  // its device seconds. Rows of a level are launched in chunks (global id offsets) so that progress
  // can follow within a level: the first levels hold most of the texels and take most of the time.
  double run_level(int l, int n, double r, std::vector<float>& dst, const std::function<void(double)>& step) {
    const int size = out_.level_size(l);
    const LevelInputs in = level_inputs(l, n, r);
    // the level is written into dst through USE_HOST_PTR and mapped back: no second copy on a
    // CPU device
    dst.assign(4 * face_texels(size), 0.0f);
    check_allocation(dev_, dst.size() * sizeof(float), "level " + std::to_string(l));
    cl::Buffer dst_buf(dev_.context, CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR, dst.size() * sizeof(float), dst.data());
    // The quadrature a block of 8 x 8 texels at a time where the block divides the level
    // (prefilter_pyramid_strips), else (and with s.strips off) a walk per texel
    // (prefilter_pyramid).
    const bool strips = quadrature_ && use_strips(size);
    const int unit = strips ? 2 * kStripRows : 1;
    StripBright sb;
    if (strips) sb = strip_bright(in);
    // Launches over bands of `unit` rows (whole blocks), each sized from the speed the previous
    // ones measured to take about 50 ms (runtime/launch.hpp: no display watchdog is approached on
    // a GPU, a stop waits for one launch, progress follows the parts). A band's cost in
    // LaunchSizer's units: its texels times ~64 evaluations (pyramid texels or samples) each.
    const size_t texel_group = per_texel_group(size);
    const size_t bands = size_t(6 * size / unit);
    const double band_cost = double(size) * double(unit) * 64.0;
    const double level_seconds = launch_in_parts(
        bands, band_cost,
        [&](size_t first, size_t count) -> cl::Event {
          const size_t row0 = first * size_t(unit), n_rows = count * size_t(unit);
          const cl::EnqueueArgs range =
              strips ? cl::EnqueueArgs(dev_.queue, cl::NDRange(0, first), cl::NDRange(size_t(size / 8), count),
                                       cl::NDRange(1, 1))
              : texel_group > 0
                  ? cl::EnqueueArgs(dev_.queue, cl::NDRange(0, row0), cl::NDRange(size_t(size), n_rows),
                                    cl::NDRange(texel_group, 1))
                  : cl::EnqueueArgs(dev_.queue, cl::NDRange(0, row0), cl::NDRange(size_t(size), n_rows), cl::NullRange);
          return launch(size, dst_buf, in, sb, strips, range);
        },
        step, step ? 4 : 1);  // a progress line moves within a level
    void* mapped = dev_.queue.enqueueMapBuffer(dst_buf, CL_TRUE, CL_MAP_READ, 0, dst.size() * sizeof(float));
    dev_.queue.enqueueUnmapMemObject(dst_buf, mapped);
    dev_.queue.finish();
    return level_seconds;
  }

  // The kernel shape (docs/DEVICES.md, "Kernel shapes"): the CPU shape walks the quadrature a block
  // of 8 x 8 texels a work-item (prefilter_pyramid_strips, float16 vectors: what PoCL's vectoriser
  // fills; `strips` off: a walk per texel, the accuracy reference of the bench and tests), where the
  // block divides the level; the GPU shape a texel a work-item (prefilter_pyramid), in work-groups
  // of a row's neighbouring texels (per_texel_group), so that a 128^2 level is 98,304 work-items,
  // not 1,536 blocks.
  bool use_strips(int size) const {
    return s_.strips && dev_.info.kernel_shape != "gpu" && size % 8 == 0 && size % (2 * kStripRows) == 0;
  }
  // The work-group of the per-texel kernels in the GPU shape: up to 64 texels of a row (their walks
  // refine nearly the same pyramid texels: the warp's branches agree), within the device's limit;
  // 0 (the implementation chooses) in the CPU shape, as before.
  size_t per_texel_group(int size) const {
    if (dev_.info.kernel_shape != "gpu") return 0;
    size_t g = std::min<size_t>({64, size_t(size), std::max<size_t>(1, dev_.info.max_work_group_size)});
    while (g > 1 && size_t(size) % g != 0) --g;
    return g;
  }

  // One launch of the level's kernel over `range`, in the spec's precision.
  cl::Event launch(int size, const cl::Buffer& dst_buf, const LevelInputs& in, const StripBright& sb, bool strips,
                   const cl::EnqueueArgs& range) {
    const bool fp64 = s_.precision == Precision::Fp64;
    cl::Program& prog = filter_prog_;
    const Pyramid& p = pyramid_;
    if (strips)
      return fp64 ? launch_strips<cl_double>(prog, dst_buf, size, pyramid_buf_, pyramid_info_, p.levels, in.core_buf,
                                             in.band_buf, sb, in.alpha, range)
                  : launch_strips<cl_float>(prog, dst_buf, size, pyramid_buf_, pyramid_info_, p.levels, in.core_buf,
                                            in.band_buf, sb, in.alpha, range);
    if (quadrature_)
      return fp64 ? launch_pyramid<cl_double>(prog, dst_buf, size, pyramid_buf_, pyramid_info_, p.levels, in.core_buf,
                                              in.band_buf, in.pts_buf, in.n_pts, in.alpha, range)
                  : launch_pyramid<cl_float>(prog, dst_buf, size, pyramid_buf_, pyramid_info_, p.levels, in.core_buf,
                                             in.band_buf, in.pts_buf, in.n_pts, in.alpha, range);
    return fp64 ? launch_level<cl_double>(prog, dst_buf, size, chain_, in.table_buf, in.n_padded, in.pts_buf, in.n_pts,
                                          in.alpha, range)
                : launch_level<cl_float>(prog, dst_buf, size, chain_, in.table_buf, in.n_padded, in.pts_buf, in.n_pts,
                                         in.alpha, range);
  }

  Device::Impl& dev_;
  const PrefilterSpec& s_;
  const int levels_, s0_;
  const bool quadrature_;
  CubeLevels out_;
  std::vector<BrightTexel> bright_;
  ChainRecord rec_;
  std::chrono::steady_clock::time_point stage_mark_ = std::chrono::steady_clock::now();
  double device_seconds_ = 0.0;
  cl::Program filter_prog_;
  Pyramid pyramid_;
  cl::Buffer pyramid_buf_, pyramid_info_;
  PaddedChain chain_;
};

}  // namespace

cl::Program filter_program(Device::Impl& dev, const PrefilterSpec& s) {
  const char* lobe_define = s.distribution == EnvDistribution::Charlie ? "BRDFBAKE_ENV_CHARLIE" : "BRDFBAKE_ENV_GGX";
  return env_program(dev, "prefilter.cl", s.precision,
                     {{lobe_define, "1"}, {"BRDFBAKE_STRIP_ROWS", std::to_string(kStripRows)}});
}

namespace {

CubeLevels chain_of(Device& device, CubeLevels source, const PrefilterSpec& in, PrefilterTiming* timing,
                    const EnvProgress& progress, const std::vector<double>* roughness) {
  const auto t0 = std::chrono::steady_clock::now();
  const PrefilterSpec s = resolve_prefilter_spec(in);
  if (source.levels.empty() || source.size != s.size)
    throw Error("prefilter_cube: the source cube must have size " + std::to_string(s.size));
  auto& dev = device.impl();
  if (roughness && roughness->size() != size_t(prefilter_level_count(s)))
    throw Error("prefilter_chain_at: " + std::to_string(roughness->size()) + " roughnesses for a chain of " +
                std::to_string(prefilter_level_count(s)) + " levels");
  ChainBaker baker(dev, s, std::move(source), roughness);
  double device_seconds = 0.0;
  const std::string what = "prefiltering on '" + dev.info.name + "'";
  cl_call(what, [&] {
    device_seconds = baker.bake(progress);
    return 0;
  });
  CubeLevels& out = baker.out();
  const ChainRecord& rec = baker.record();
  chain_metadata(out, s, rec);
  out.set_meta("precision", precision_name(s.precision));
  out.set_meta("device", dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  if (timing) {
    timing->stage_seconds.insert(timing->stage_seconds.end(), rec.stages.begin(), rec.stages.end());
    timing->device_seconds += device_seconds;
    timing->level_device_seconds = rec.seconds;
    if (s.max_error > 0.0) {
      timing->measured_error_per_level = rec.measured;
      timing->measured_error = *std::max_element(rec.measured.begin(), rec.measured.end());
    }
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return std::move(out);
}

}  // namespace

CubeLevels prefilter_chain(Device& device, CubeLevels source, const PrefilterSpec& in, PrefilterTiming* timing,
                           const EnvProgress& progress) {
  return chain_of(device, std::move(source), in, timing, progress, nullptr);
}

CubeLevels prefilter_chain_at(Device& device, CubeLevels source, const PrefilterSpec& spec,
                              const std::vector<double>& roughness, PrefilterTiming* timing) {
  return chain_of(device, std::move(source), spec, timing, {}, &roughness);
}

}  // namespace brdfbake::detail
