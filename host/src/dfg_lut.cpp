// The DFG lookup tables on the device (kernels/dfg_lut.cl); the reference backend's bake_lut_reference
// is host/src/reference_backend/dfg_lut.cpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "brdfbake/error.hpp"
#include "brdfbake/lut.hpp"
#include "brdfbake/math/gauss_legendre.hpp"
#include "brdfbake/version.hpp"
#include "dfg_lut_internal.hpp"
#include "runtime/program.hpp"

namespace brdfbake {

namespace {

struct Named {
  const char* name;
  int value;
};

template <class E, size_t N>
E from_name(const Named (&table)[N], const std::string& name, const char* what) {
  std::string expected;
  for (const auto& t : table) {
    if (name == t.name) return static_cast<E>(t.value);
    expected += (expected.empty() ? "" : ", ") + std::string(t.name);
  }
  throw Error("unknown " + std::string(what) + " '" + name + "' (expected " + expected + ")");
}

template <class E, size_t N>
const char* to_name(const Named (&table)[N], E value) {
  for (const auto& t : table)
    if (t.value == static_cast<int>(value)) return t.name;
  return "?";
}

const Named kKinds[] = {{"ggx", int(LutKind::Ggx)},
                        {"ggx-multiscatter", int(LutKind::GgxMultiscatter)},
                        {"charlie", int(LutKind::Charlie)}};
const Named kEstimators[] = {{"quadrature", int(Estimator::Quadrature)},
                             {"vndf", int(Estimator::Vndf)},
                             {"ndf", int(Estimator::Ndf)},
                             {"uniform", int(Estimator::Uniform)}};
const Named kVisibilities[] = {{"estevez-kulla", int(SheenVisibility::EstevezKulla)},
                               {"neubelt", int(SheenVisibility::Neubelt)}};

// Calibration: max abs error over every channel of the 128x128 table against the converged
// reference, measured by bench/lut_accuracy (docs/BENCHMARKS.md). Sorted by samples.
struct Calibration {
  LutKind kind;
  Estimator estimator;
  Precision precision;
  int samples;
  double max_error;
};
const Calibration kCalibration[] = {
#include "dfg_lut_calibration.inc"
};

// Default evaluations per texel of each estimator: the smallest calibrated count whose error is
// within kDefaultBound, so that the default table meets it (DEVELOPERS' accuracy goal).
constexpr double kDefaultBound = 1e-4;
constexpr int kFallbackSamples = 1024;
constexpr long long kMaxTexels = 1ll << 26;

int default_samples(LutKind kind, Estimator estimator, Precision precision) {
  for (const auto& c : kCalibration)
    if (c.kind == kind && c.estimator == estimator && c.precision == precision &&
        c.max_error <= kDefaultBound)
      return c.samples;
  return kFallbackSamples;
}

// The quadrature's split of `samples` evaluations per texel: n_xi nodes in the polar variable and
// n_phi in azimuth, on each of the two panels (2 n_xi n_phi evaluations). The azimuth converges
// much faster than the polar angle (docs/BENCHMARKS.md), so n_phi stays small until the polar rule
// is long. The kernel runs 8 polar nodes at once: n_xi is rounded up to a multiple of 8.
void quadrature_shape(LutKind kind, int samples, int& n_xi, int& n_phi) {
  constexpr int kWidth = 8;  // BRDFBAKE_LANES: n_xi is a multiple of it
  // GGX's azimuth rule limits it to ~1e-5 with 8 nodes (grazing, low roughness), so it doubles
  // them early; Charlie's band needs polar nodes first (measured: docs/BENCHMARKS.md).
  const int to16 = kind == LutKind::Charlie ? 2048 : 768;
  const int to32 = kind == LutKind::Charlie ? 8192 : 4096;
  n_phi = samples < 128 ? std::max(1, samples / (2 * kWidth)) : samples < to16 ? 8 : samples < to32 ? 16 : 32;
  n_xi = std::max(kWidth, (samples / (2 * n_phi) + kWidth - 1) / kWidth * kWidth);
}

int evaluations(const LutSpec& s) {
  if (s.estimator != Estimator::Quadrature) return s.samples;
  int n_xi = 0, n_phi = 0;
  quadrature_shape(s.kind, s.samples, n_xi, n_phi);
  return 2 * n_xi * n_phi;
}

std::string fmt(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

}  // namespace

Table detail::make_lut_table(const LutSpec& s) {
  Table t;
  t.width = static_cast<int>(s.n_dot_v.size());
  t.height = static_cast<int>(s.roughness.size());
  t.channels = lut_channels(s.kind);
  t.x_name = "n_dot_v";
  t.y_name = s.kind == LutKind::Charlie ? "sheen_roughness" : "roughness";
  t.x = s.n_dot_v;
  t.y = s.roughness;
  t.data.assign(static_cast<size_t>(t.width) * static_cast<size_t>(t.height) * t.channels.size(), 0.f);
  t.set_meta("generator", std::string("brdfbake ") + kVersion);
  t.set_meta("kind", lut_kind_name(s.kind));
  t.set_meta("width", std::to_string(t.width));
  t.set_meta("height", std::to_string(t.height));
  std::string channels;
  for (const auto& c : t.channels) channels += (channels.empty() ? "" : ",") + c;
  t.set_meta("channels", channels);
  const std::string rough = s.kind == LutKind::Charlie ? "sheen_roughness" : "roughness";
  const bool sx = s.n_dot_v_axis == LutAxis::Sqrt, sy = s.roughness_axis == LutAxis::Sqrt;
  t.set_meta("x_axis", std::string("n_dot_v = ") + (sx ? "((i + 0.5) / width)^2" : "(i + 0.5) / width") +
                           ", at the cell centre of column i");
  t.set_meta("y_axis", rough + " = " + (sy ? "((j + 0.5) / height)^2" : "(j + 0.5) / height") +
                           ", perceptual, at the cell centre of row j; alpha = " + rough + "^2");
  t.set_meta("n_dot_v_axis", lut_axis_name(s.n_dot_v_axis));
  t.set_meta("roughness_axis", lut_axis_name(s.roughness_axis));
  t.set_meta("layout", "row j = 0 (smallest roughness) stored first; sample at uv = (" +
                           std::string(sx ? "sqrt(n_dot_v)" : "n_dot_v") + ", " + (sy ? "sqrt(" + rough + ")" : rough) + ")");
  t.set_meta("lookup", std::string("uv = (") + (sx ? "sqrt(n_dot_v)" : "n_dot_v") + ", " +
                           (sy ? "sqrt(" + rough + ")" : rough) + "), bilinear, clamp to edge");
  switch (s.kind) {
    case LutKind::Ggx:
      t.set_meta("definition",
                 "scale = int (1 - Fc) D V n.l dl, bias = int Fc D V n.l dl, Fc = (1 - v.h)^5, GGX D, "
                 "height-correlated Smith V (Heitz 2014); specular = F0 * scale + F90 * bias; "
                 "diffuse = int f_Burley n.l dl (Burley 2012, F_D90 = 0.5 + 2 roughness (l.h)^2)");
      break;
    case LutKind::GgxMultiscatter:
      t.set_meta("definition",
                 "bias = int Fc D V n.l dl, albedo = int D V n.l dl (= scale + bias), GGX with "
                 "height-correlated Smith V; diffuse = Burley 2012 directional albedo");
      t.set_meta("runtime",
                 "specular = mix(bias, albedo, F0) * (1 + F0 * (1 / albedo - 1)) (Kulla & Conty 2017 "
                 "energy compensation, Filament's formulation)");
      break;
    case LutKind::Charlie:
      t.set_meta("definition", "albedo = int D_Charlie V n.l dl (Estevez & Kulla 2017), sheen colour 1");
      t.set_meta("sheen_visibility", sheen_visibility_name(s.sheen_visibility));
      break;
  }
  return t;
}

namespace {

// A Gauss-Legendre rule mapped to [0, 1].
struct Rule01 {
  std::vector<double> x, w;
};
Rule01 rule01(int n) {
  const auto& r = math::gauss_legendre(n);
  Rule01 out;
  for (size_t k = 0; k < r.nodes.size(); ++k) {
    out.x.push_back(0.5 * (1.0 + r.nodes[k]));
    out.w.push_back(0.5 * r.weights[k]);
  }
  return out;
}

bool has_custom_points(const LutSpec& in) { return !in.n_dot_v.empty() || !in.roughness.empty(); }

}  // namespace

LutKind lut_kind_from_name(const std::string& n) { return from_name<LutKind>(kKinds, n, "table kind"); }
const char* lut_kind_name(LutKind k) { return to_name(kKinds, k); }
Estimator estimator_from_name(const std::string& n) {
  return from_name<Estimator>(kEstimators, n, "estimator");
}
const char* estimator_name(Estimator e) { return to_name(kEstimators, e); }
SheenVisibility sheen_visibility_from_name(const std::string& n) {
  return from_name<SheenVisibility>(kVisibilities, n, "sheen visibility");
}
const char* sheen_visibility_name(SheenVisibility v) { return to_name(kVisibilities, v); }

LutAxis lut_axis_from_name(const std::string& n) {
  if (n == "uniform") return LutAxis::Uniform;
  if (n == "sqrt") return LutAxis::Sqrt;
  throw Error("unknown axis '" + n + "' (expected uniform or sqrt)");
}
const char* lut_axis_name(LutAxis a) { return a == LutAxis::Sqrt ? "sqrt" : "uniform"; }
double lut_axis_uv(LutAxis a, double x) { return a == LutAxis::Sqrt ? std::sqrt(std::max(0.0, x)) : x; }
double lut_axis_value(LutAxis a, double uv) { return a == LutAxis::Sqrt ? uv * uv : uv; }

std::vector<std::string> lut_channels(LutKind kind) {
  switch (kind) {
    case LutKind::Ggx: return {"scale", "bias", "diffuse"};
    case LutKind::GgxMultiscatter: return {"bias", "albedo", "diffuse"};
    case LutKind::Charlie: break;
  }
  return {"albedo"};
}

LutSpec resolve_lut_spec(const LutSpec& in) {
  LutSpec s = in;
  if (has_custom_points(s)) {
    if (s.n_dot_v.empty() || s.roughness.empty())
      throw Error("explicit table points need both n_dot_v and roughness values");
    for (double v : s.n_dot_v)
      if (!std::isfinite(v)) throw Error("n_dot_v must be finite");
    for (double v : s.roughness)
      if (!std::isfinite(v)) throw Error("roughness must be finite");
    s.width = static_cast<int>(s.n_dot_v.size());
    s.height = static_cast<int>(s.roughness.size());
  } else {
    if (s.height == 0) s.height = s.width;
    if (s.width < 1 || s.height < 1)
      throw Error("table size must be at least 1x1 (got " + std::to_string(s.width) + "x" +
                  std::to_string(s.height) + ")");
    if (s.width > kLutMaxSize || s.height > kLutMaxSize)
      throw Error("table size must be at most " + std::to_string(kLutMaxSize) + " per side");
  }
  if (static_cast<long long>(s.width) * s.height > kMaxTexels)
    throw Error("table has too many texels (at most " + std::to_string(kMaxTexels) + ")");
  if (s.samples < 0) throw Error("samples must be positive (got " + std::to_string(s.samples) + ")");
  if (s.estimator == Estimator::Quadrature && s.samples > kLutMaxQuadratureSamples)
    throw Error("the quadrature takes at most " + std::to_string(kLutMaxQuadratureSamples) +
                " evaluations per texel (got " + std::to_string(s.samples) + "; its error is below 1e-7 long before)");
  if (s.samples > kLutMaxSamples)
    throw Error("samples must be at most " + std::to_string(kLutMaxSamples) + " (got " + std::to_string(s.samples) + ")");
  if (std::isnan(s.max_error) || s.max_error < 0.0)
    throw Error("max-error must be a positive number");
  const bool ggx = s.kind != LutKind::Charlie;
  if (ggx && s.estimator == Estimator::Uniform)
    throw Error("estimator 'uniform' is for the charlie table only");
  if (!ggx && s.estimator == Estimator::Vndf)
    throw Error("estimator 'vndf' samples GGX visible normals; the charlie table takes quadrature, ndf or uniform");
  if (s.max_error > 0.0) {
    if (s.samples > 0) throw Error("give either samples or max-error, not both");
    int best = 0;
    double best_error = -1.0;
    for (const auto& c : kCalibration) {
      if (c.kind != s.kind || c.estimator != s.estimator || c.precision != s.precision) continue;
      if (c.max_error <= s.max_error) {
        best = c.samples;
        break;
      }
      best_error = best_error < 0 ? c.max_error : std::min(best_error, c.max_error);
    }
    if (best == 0)
      throw Error("no calibrated sample count of estimator '" + std::string(estimator_name(s.estimator)) +
                  "' reaches max-error " + fmt(s.max_error) + " for " + lut_kind_name(s.kind) +
                  (best_error > 0 ? " (the best measured is " + fmt(best_error) + ")" : ""));
    s.samples = best;
  }
  if (s.samples == 0) s.samples = default_samples(s.kind, s.estimator, s.precision);
  if (!has_custom_points(s)) {
    s.n_dot_v.resize(static_cast<size_t>(s.width));
    s.roughness.resize(static_cast<size_t>(s.height));
    for (int i = 0; i < s.width; ++i) s.n_dot_v[static_cast<size_t>(i)] = lut_axis_value(s.n_dot_v_axis, (i + 0.5) / s.width);
    for (int j = 0; j < s.height; ++j)
      s.roughness[static_cast<size_t>(j)] = lut_axis_value(s.roughness_axis, (j + 0.5) / s.height);
  }
  return s;
}

double lut_error_bound(LutKind kind, Estimator estimator, Precision precision, int samples, int* measured_at) {
  double bound = -1.0;
  int at = 0;
  for (const auto& c : kCalibration)
    if (c.kind == kind && c.estimator == estimator && c.precision == precision && c.samples <= samples &&
        c.samples >= at) {
      bound = c.max_error;
      at = c.samples;
    }
  if (measured_at) *measured_at = at;
  return bound;
}

Table bake_lut(Device& device, const LutSpec& in, LutTiming* timing, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const LutSpec s = resolve_lut_spec(in);
  auto& dev = device.impl();

  detail::ProgramSpec ps;
  ps.file = "dfg_lut.cl";
  ps.precision = s.precision;
  ps.defines.push_back({s.kind == LutKind::Ggx               ? "BRDFBAKE_LUT_GGX"
                        : s.kind == LutKind::GgxMultiscatter ? "BRDFBAKE_LUT_GGX_MULTISCATTER"
                                                             : "BRDFBAKE_LUT_CHARLIE",
                        "1"});
  const char* est = s.estimator == Estimator::Quadrature ? "BRDFBAKE_EST_QUADRATURE"
                    : s.estimator == Estimator::Vndf     ? "BRDFBAKE_EST_VNDF"
                    : s.estimator == Estimator::Ndf      ? "BRDFBAKE_EST_NDF"
                                                         : "BRDFBAKE_EST_UNIFORM";
  ps.defines.push_back({est, "1"});
  if (s.kind == LutKind::Charlie && s.sheen_visibility == SheenVisibility::Neubelt)
    ps.defines.push_back({"BRDFBAKE_SHEEN_NEUBELT", "1"});
  cl::Program program = detail::build_program(dev, ps);

  // Quadrature nodes (layout documented in kernels/dfg_lut.cl).
  int n_xi = 1, n_phi = 1;
  if (s.estimator == Estimator::Quadrature) quadrature_shape(s.kind, s.samples, n_xi, n_phi);
  std::vector<double> q;
  const Rule01 gl_xi = rule01(n_xi), gl_phi = rule01(n_phi), gl_d = rule01(8);
  q.insert(q.end(), gl_xi.x.begin(), gl_xi.x.end());
  q.insert(q.end(), gl_xi.w.begin(), gl_xi.w.end());
  for (double x : gl_xi.x) q.push_back(0.5 * (1.0 - std::cos(M_PI * x)));
  for (size_t k = 0; k < gl_xi.x.size(); ++k) q.push_back(0.5 * M_PI * std::sin(M_PI * gl_xi.x[k]) * gl_xi.w[k]);
  q.insert(q.end(), gl_phi.x.begin(), gl_phi.x.end());
  q.insert(q.end(), gl_phi.w.begin(), gl_phi.w.end());
  for (int m = 0; m < n_phi; ++m) q.push_back(std::cos((m + 0.5) * M_PI / n_phi));
  q.insert(q.end(), gl_d.x.begin(), gl_d.x.end());
  q.insert(q.end(), gl_d.w.begin(), gl_d.w.end());

  Table t = detail::make_lut_table(s);
  const std::string what = "kernel dfg_lut on '" + dev.info.name + "'";
  double device_seconds = detail::cl_call(what, [&] {
    auto real_buffer = [&](const std::vector<double>& v) {
      if (s.precision == Precision::Fp64)
        return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(double),
                          const_cast<double*>(v.data()));
      std::vector<float> f(v.begin(), v.end());
      return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float),
                        f.data());
    };
    cl::Buffer xs = real_buffer(s.n_dot_v), ys = real_buffer(s.roughness), qb = real_buffer(q);
    cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, t.data.size() * sizeof(float));
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl_int, cl_uint, cl::Buffer, cl_int, cl_int>
        dfg(program, "dfg_lut");
    // Rows go in chunks so that a progress line can follow them; the launches are queued, and
    // each costs a few microseconds.
    const int chunks = progress ? std::min(s.height, 16) : 1;
    std::vector<cl::Event> events;
    for (int c = 0; c < chunks; ++c) {
      const int j0 = static_cast<int>(static_cast<long long>(s.height) * c / chunks);
      const int j1 = static_cast<int>(static_cast<long long>(s.height) * (c + 1) / chunks);
      if (j1 <= j0) continue;
      events.push_back(dfg(cl::EnqueueArgs(dev.queue, cl::NDRange(0, static_cast<size_t>(j0)),
                                           cl::NDRange(static_cast<size_t>(s.width), static_cast<size_t>(j1 - j0)),
                                           cl::NullRange),
                           out, xs, ys, s.width, s.height, static_cast<cl_uint>(s.samples), qb, n_xi, n_phi));
    }
    double seconds = 0.0;
    for (size_t c = 0; c < events.size(); ++c) {
      events[c].wait();
      seconds += detail::event_seconds(events[c]);
      if (progress) progress(static_cast<double>(c + 1) / static_cast<double>(events.size()));
    }
    dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, t.data.size() * sizeof(float), t.data.data());
    return seconds;
  });

  t.set_meta("device", dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  t.set_meta("precision", precision_name(s.precision));
  t.set_meta("estimator", estimator_name(s.estimator));
  t.set_meta("samples", std::to_string(s.samples));
  t.set_meta("evaluations_per_texel", std::to_string(evaluations(s)));
  int measured_at = 0;
  const double bound = lut_error_bound(s.kind, s.estimator, s.precision, s.samples, &measured_at);
  t.set_meta("error_bound", bound >= 0 ? fmt(bound) : "not measured");
  if (bound >= 0 && measured_at != s.samples)
    t.set_meta("error_bound_measured_at", std::to_string(measured_at) + " samples (the largest measured count below " +
                                              std::to_string(s.samples) + ")");
  t.set_meta("error_bound_definition",
             "max error (abs below 1, relative above) over every channel of the 128x128 table against "
             "the converged double reference, measured by bench/lut_accuracy at this estimator, sample "
             "count and precision, plus a 25% margin");
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return t;
}

}  // namespace brdfbake
