// BRDF tabulation on the device (kernels/brdf_eval.cl): the MERL layout, and grids, directional
// albedos and slices as tables, with their axes and metadata.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/gauss_legendre.hpp"
#include "brdfbake/version.hpp"
#include "families/brdf_eval/model.hpp"
#include "runtime/launch.hpp"
#include "runtime/program.hpp"
#include "text.hpp"

namespace brdfbake {
namespace {

using math::kPi;
constexpr double kHalfPi = 0.5 * kPi;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

const char* kConventions =
    "f is the BRDF without the cosine (radiance per irradiance, 1/sr), linear RGB; directions in tangent "
    "space, normal +z, tangent +x (Disney's alpha_x axis), bitangent +y; f = 0 where wi or wo is at or "
    "below the horizon; above it n.wi and n.wo are floored at 1e-7; roughness is perceptual, alpha = "
    "roughness^2 (docs/CONVENTIONS.md, BRDF evaluation)";

constexpr int kMaxRes = 8192;
constexpr long long kMaxCells = 1ll << 26;

// Albedo quadrature shape (kernels/brdf_eval.cl, brdf_albedo): panel A takes composite 8-point
// Gauss-Legendre panels of width <= kAlbedoPanelY in y = ln tan t, panel B kAlbedoNodesB nodes, the
// azimuth kAlbedoNodesPhi. Their accuracy is measured in tests/device and docs/BENCHMARKS.md.
constexpr double kAlbedoPanelY = 0.5;
constexpr double kAlbedoStart = 1e-4;
constexpr double kAlbedoStartMax = 1e-5;
constexpr int kAlbedoNodesB = 96;
constexpr int kAlbedoNodesPhi = 64;

}  // namespace

void detail::check_tabulate_spec(const TabulateSpec& s) {
  if (s.materials.empty()) throw Error("no materials to tabulate");
  if (s.layout != TableLayout::Albedo && s.materials.size() != 1)
    throw Error(std::string("layout ") + table_layout_name(s.layout) + " tabulates one material (got " +
                std::to_string(s.materials.size()) + ")");
  for (const NamedMaterial& m : s.materials) validate_material(m.params, "material '" + m.name + "'");
  if (!(s.slice_phi_d >= 0.0 && s.slice_phi_d <= kPi))
    throw Error("slice phi_d must be in [0, pi] (got " + detail::fmt_number(s.slice_phi_d, "%.6g") + ")");
}

namespace {

std::vector<Material> params_of(const TabulateSpec& s) {
  std::vector<Material> v;
  for (const NamedMaterial& m : s.materials) v.push_back(m.params);
  return v;
}

}  // namespace

void detail::tabulate_metadata(Metadata& meta, const TabulateSpec& s, const std::vector<int>& res,
                               const std::string& device, const std::string& precision, const std::string& lobes) {
  auto set = [&](const std::string& k, const std::string& v) {
    for (auto& kv : meta)
      if (kv.first == k) {
        kv.second = v;
        return;
      }
    meta.emplace_back(k, v);
  };
  set("generator", std::string("brdfbake ") + kVersion);
  set("model", brdf_model_name(s.model));
  std::string materials = "[";
  for (size_t i = 0; i < s.materials.size(); ++i) materials += (i ? "," : "") + material_to_json(s.materials[i]);
  set("materials", materials + "]");
  set("layout", table_layout_name(s.layout));
  std::string r;
  for (int v : res) r += (r.empty() ? "" : "x") + std::to_string(v);
  set("resolution", r);
  set("precision", precision);
  set("device", device);
  set("lobes", lobes);
  set("conventions", kConventions);
}

namespace {

std::string device_name(Device::Impl& dev) {
  return dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")";
}

std::string precision_label(const EvalOptions& o) {
  return std::string(precision_name(o.precision)) + (o.fast_math ? " -cl-fast-relaxed-math" : "");
}

}  // namespace

Table detail::make_tabulate_table(const TabulateSpec& s, const std::vector<int>& res) {
  Table t;
  t.channels = {"r", "g", "b"};
  switch (s.layout) {
    case TableLayout::Grid: {
      const int ni = res[0], no = res[1], np = res[2];
      t.width = no;
      t.height = ni * np;
      t.x_name = "theta_o";
      t.y_name = "theta_i";
      for (int j = 0; j < no; ++j) t.x.push_back((j + 0.5) / no * kHalfPi);
      for (int k = 0; k < np; ++k)
        for (int i = 0; i < ni; ++i) t.y.push_back((i + 0.5) / ni * kHalfPi);
      t.set_meta("axes", "column j: theta_o = (j + 0.5) / " + std::to_string(no) + " pi/2; row k * " +
                             std::to_string(ni) + " + i: theta_i = (i + 0.5) / " + std::to_string(ni) +
                             " pi/2, phi_d = (k + 0.5) / " + std::to_string(np) +
                             " pi; wi = (sin theta_i, 0, cos theta_i), wo = (sin theta_o cos phi_d, "
                             "sin theta_o sin phi_d, cos theta_o); angles in radians");
      break;
    }
    case TableLayout::Albedo: {
      const int n = res[0];
      t.width = n;
      t.height = static_cast<int>(s.materials.size());
      t.x_name = "theta_o";
      t.y_name = "material";
      for (int i = 0; i < n; ++i) t.x.push_back((i + 0.5) / n * kHalfPi);
      std::string names;
      for (size_t m = 0; m < s.materials.size(); ++m) {
        t.y.push_back(static_cast<double>(m));
        names += (m ? "," : "") + s.materials[m].name;
      }
      t.set_meta("axes", "column i: theta_o = (i + 0.5) / " + std::to_string(n) +
                             " pi/2 (radians), wo = (sin theta_o, 0, cos theta_o); row m: material m");
      t.set_meta("material_names", names);
      t.set_meta("definition", "directional albedo a(wo) = integral over the hemisphere of f(wi, wo) n.wi dwi");
      break;
    }
    case TableLayout::Slice: {
      const int w = res[0], h = res[1];
      t.width = w;
      t.height = h;
      t.x_name = "theta_h";
      t.y_name = "theta_d";
      for (int i = 0; i < w; ++i) t.x.push_back((i + 0.5) / w * kHalfPi);
      for (int j = 0; j < h; ++j) t.y.push_back((j + 0.5) / h * kHalfPi);
      t.set_meta("axes", "column i: theta_h = (i + 0.5) / " + std::to_string(w) +
                             " pi/2, row j: theta_d = (j + 0.5) / " + std::to_string(h) +
                             " pi/2, phi_d = " + detail::fmt_number(s.slice_phi_d, "%.6g") +
                             ", phi_h = 0 (Rusinkiewicz half/difference angles, radians); wi = R_y(theta_h) d, "
                             "wo = 2 (wi.h) h - wi; 0 where a direction is below the horizon");
      t.set_meta("phi_d", detail::fmt_number(s.slice_phi_d, "%.6g"));
      break;
    }
    case TableLayout::Merl:
      break;
  }
  t.data.assign(static_cast<size_t>(t.width) * static_cast<size_t>(t.height) * 3, 0.0f);
  return t;
}

void detail::merl_metadata(Metadata& meta) {
  meta.emplace_back("merl_layout",
                    "bin (i, j, k) of theta_h, theta_d, phi_d holds f at theta_h = ((i + 0.5)/90)^2 pi/2, theta_d = "
                    "(j + 0.5)/90 pi/2, phi_d = (k + 0.5)/180 pi, phi_h = 0, stored as f / scale with scale = "
                    "1/1500, 1.15/1500, 1.66/1500 (red, green, blue); -1 where a direction is below the horizon");
}

namespace {

// The albedo quadrature nodes (layout in kernels/brdf_eval.cl, brdf_albedo).
std::vector<double> albedo_nodes(int n_a, int n_b, int n_p) {
  std::vector<double> q;
  const auto& g8 = math::gauss_legendre(8);
  const int panels = n_a / 8;
  std::vector<double> xa, wa;
  for (int p = 0; p < panels; ++p)
    for (size_t k = 0; k < 8; ++k) {
      xa.push_back((p + 0.5 * (1.0 + g8.nodes[k])) / panels);
      wa.push_back(0.5 * g8.weights[k] / panels);
    }
  q.insert(q.end(), xa.begin(), xa.end());
  q.insert(q.end(), wa.begin(), wa.end());
  const auto& gb = math::gauss_legendre(n_b);
  for (int k = 0; k < n_b; ++k) q.push_back(0.5 * (1.0 - std::cos(kPi * 0.5 * (1.0 + gb.nodes[size_t(k)]))));
  for (int k = 0; k < n_b; ++k) {
    const double x = 0.5 * (1.0 + gb.nodes[size_t(k)]);
    q.push_back(0.5 * kPi * std::sin(kPi * x) * 0.5 * gb.weights[size_t(k)]);
  }
  for (int j = 0; j < n_p; ++j) q.push_back(std::cos((j + 0.5) * kPi / n_p));
  for (int j = 0; j < n_p; ++j) q.push_back(std::sin((j + 0.5) * kPi / n_p));
  const auto& gp = math::gauss_legendre(n_p);
  for (int j = 0; j < n_p; ++j) q.push_back(0.5 * (1.0 + gp.nodes[size_t(j)]));
  for (int j = 0; j < n_p; ++j) q.push_back(0.5 * gp.weights[size_t(j)]);
  return q;
}

// What a grid, albedo or slice bake launches with.
struct TabulateLaunch {
  Device::Impl& dev;
  const TabulateSpec& s;
  const std::vector<int>& res;
  const std::vector<Material>& mats;
  cl::Program& program;
  const cl::Buffer& params;
  const cl::Buffer& sheen;
  int lanes;
};

// The albedo layout: each albedo a whole quadrature over the half vector (brdf_albedo), in bounded
// launches over theta_o; returns the device seconds.
double tabulate_albedo(const TabulateLaunch& k, Table& t) {
  Device::Impl& dev = k.dev;
  const TabulateSpec& s = k.s;
  const std::vector<int>& res = k.res;
  const std::vector<Material>& mats = k.mats;
  const Precision prec = s.options.precision;
  const int lanes = k.lanes;
  cl::Program& program = k.program;
  const cl::Buffer &params = k.params, &sheen = k.sheen;
  double launched = 0.0;
  std::vector<double> planes;
  size_t plane = 0;
  const int n = res[0];
  double y_lowest = 0.0;
  std::vector<double> y_min;
  for (const Material& m : mats) {
    // the polar angles below 1e-4 of the narrowest lobe (and below 1e-5 rad) hold less than
    // 1e-8 of its albedo: the integrand grows like t^2 there (dh = sin t dt)
    y_min.push_back(std::log(std::min(kAlbedoStart * detail::narrowest_lobe(s.model, m), kAlbedoStartMax)));
    y_lowest = std::min(y_lowest, y_min.back());
  }
  const int n_a = 8 * std::max(1, static_cast<int>(std::ceil(-y_lowest / kAlbedoPanelY)));
  const int n_a_padded = (n_a + lanes - 1) / lanes * lanes;
  std::vector<double> q = albedo_nodes(n_a, kAlbedoNodesB, kAlbedoNodesPhi);
  // pad panel A with zero-weight nodes to a multiple of the lane width
  std::vector<double> qa(q.begin(), q.begin() + n_a), wa(q.begin() + n_a, q.begin() + 2 * n_a);
  qa.resize(static_cast<size_t>(n_a_padded), 0.5);
  wa.resize(static_cast<size_t>(n_a_padded), 0.0);
  std::vector<double> qq = qa;
  qq.insert(qq.end(), wa.begin(), wa.end());
  qq.insert(qq.end(), q.begin() + 2 * n_a, q.end());
  cl::Buffer qb = detail::brdf_real_buffer(dev, prec, qq), yb = detail::brdf_real_buffer(dev, prec, y_min);
  plane = static_cast<size_t>(n);
  cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, 3 * mats.size() * plane * detail::real_size(prec));
  cl::KernelFunctor<cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl::Buffer, cl_int, cl_int, cl_int, cl::Buffer> kernel(
      program, "brdf_albedo");
  // Every albedo is a whole quadrature: bounded launches over theta_o (runtime/launch.hpp).
  const double nodes = double(n_a_padded + kAlbedoNodesB) * kAlbedoNodesPhi * double(mats.size());
  launched = detail::launch_in_parts(static_cast<size_t>(n), nodes, [&](size_t first, size_t count) {
    return kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(first, 0), cl::NDRange(count, mats.size()), cl::NullRange),
                  params, sheen, yb, n, qb, n_a_padded, kAlbedoNodesB, kAlbedoNodesPhi, out);
  });
  planes.resize(3 * mats.size() * plane);
  detail::read_reals(dev, prec, out, planes.size(), planes.data());
  for (size_t m = 0; m < mats.size(); ++m)
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        t.at(i, static_cast<int>(m), c) = static_cast<float>(planes[(m * 3 + size_t(c)) * plane + size_t(i)]);
  return launched;
}

// The grid and slice layouts: one work-item per `lanes` cells, a BRDF evaluation each; returns the
// device seconds.
double tabulate_cells(const TabulateLaunch& k, Table& t) {
  Device::Impl& dev = k.dev;
  const TabulateSpec& s = k.s;
  const std::vector<int>& res = k.res;
  const Precision prec = s.options.precision;
  const size_t l = static_cast<size_t>(k.lanes);
  cl::Program& program = k.program;
  const cl::Buffer &params = k.params, &sheen = k.sheen;
  double launched = 0.0;
  std::vector<double> planes;
  size_t plane = 0;
  const size_t cells = static_cast<size_t>(t.width) * static_cast<size_t>(t.height);
  plane = (cells + l - 1) / l * l;
  cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, 3 * plane * detail::real_size(prec));
  // One work-item per `l` cells, a BRDF evaluation (about 8 units) each: bounded launches of items.
  const double cost = 8.0 * double(l);
  if (s.layout == TableLayout::Grid) {
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl_int, cl_int, cl_int, cl::Buffer> kernel(program, "brdf_grid");
    launched = detail::launch_in_parts(plane / l, cost, [&](size_t first, size_t count) {
      return kernel(detail::item_range(dev.queue, first, count), params, sheen, 0, res[0], res[1], res[2], out);
    });
  } else if (prec == Precision::Fp64) {
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl_int, cl_int, cl_double, cl::Buffer> kernel(program,
                                                                                                    "brdf_slice");
    launched = detail::launch_in_parts(plane / l, cost, [&](size_t first, size_t count) {
      return kernel(detail::item_range(dev.queue, first, count), params, sheen, 0, res[0], res[1], s.slice_phi_d, out);
    });
  } else {
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl_int, cl_int, cl_float, cl::Buffer> kernel(program,
                                                                                                   "brdf_slice");
    launched = detail::launch_in_parts(plane / l, cost, [&](size_t first, size_t count) {
      return kernel(detail::item_range(dev.queue, first, count), params, sheen, 0, res[0], res[1],
                    static_cast<float>(s.slice_phi_d), out);
    });
  }
  planes.resize(3 * plane);
  detail::read_reals(dev, prec, out, planes.size(), planes.data());
  for (size_t b = 0; b < cells; ++b)
    for (size_t c = 0; c < 3; ++c) t.data[b * 3 + c] = static_cast<float>(planes[c * plane + b]);
  return launched;
}

}  // namespace

std::vector<int> tabulate_resolution(const TabulateSpec& s) {
  std::vector<int> res = s.res;
  size_t want = 0;
  std::vector<int> defaults;
  switch (s.layout) {
    case TableLayout::Merl:
      if (!res.empty() && res != std::vector<int>{kMerlThetaH, kMerlThetaD, kMerlPhiD})
        throw Error("the merl layout has a fixed resolution (90 x 90 x 180); leave --res out");
      return {kMerlThetaH, kMerlThetaD, kMerlPhiD};
    case TableLayout::Grid:
      want = 3;
      defaults = {32, 32, 32};
      break;
    case TableLayout::Albedo:
      want = 1;
      defaults = {90};
      break;
    case TableLayout::Slice:
      want = 2;
      defaults = {256, 256};
      break;
  }
  if (res.empty()) res = defaults;
  if (res.size() == 1) res.assign(want, res[0]);
  if (res.size() != want)
    throw Error(std::string("layout ") + table_layout_name(s.layout) + " takes " + std::to_string(want) +
                " resolution values or one for all (got " + std::to_string(res.size()) + ")");
  long long cells = 1;
  for (int v : res) {
    if (v < 1 || v > kMaxRes)
      throw Error("resolution values must be in [1, " + std::to_string(kMaxRes) + "] (got " + std::to_string(v) + ")");
    cells *= v;
  }
  if (cells > kMaxCells) throw Error("the table has too many cells (at most " + std::to_string(kMaxCells) + ")");
  return res;
}

MerlTable tabulate_merl(Device& device, const TabulateSpec& s, TabulateTiming* timing) {
  const auto t0 = Clock::now();
  if (s.layout != TableLayout::Merl) throw Error("tabulate_merl needs the merl layout");
  detail::check_tabulate_spec(s);
  const std::vector<int> res = tabulate_resolution(s);
  auto& dev = device.impl();
  const int lanes = detail::resolve_lanes(s.options, dev.info);
  const std::vector<Material> mats = params_of(s);
  const Lobes lobes = s.options.specialize ? lobes_used(s.model, mats) : all_lobes(s.model);
  cl::Program program = detail::build_program(dev, detail::brdf_program_spec(s.model, lobes, s.options, lanes));
  const detail::PackedMaterials p = detail::pack_materials(s.model, mats);
  MerlTable t;
  t.values.resize(3 * kMerlBins);
  const Precision prec = s.options.precision;
  const double device_seconds = detail::cl_call("kernel brdf_merl on '" + dev.info.name + "'", [&] {
    cl::Buffer params = detail::brdf_real_buffer(dev, prec, p.params),
               sheen = detail::brdf_real_buffer(dev, prec, p.sheen);
    cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, 3 * kMerlBins * detail::real_size(prec));
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl_int, cl::Buffer> kernel(program, "brdf_merl");
    cl::Event e =
        kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(kMerlBins / static_cast<size_t>(lanes))), params, sheen, 0, out);
    e.wait();
    detail::read_reals(dev, prec, out, t.values.size(), t.values.data());
    return detail::event_seconds(e);
  });
  detail::tabulate_metadata(t.metadata, s, res, device_name(dev), precision_label(s.options),
                            lobes_name(s.model, lobes));
  detail::merl_metadata(t.metadata);
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = seconds_since(t0);
  }
  return t;
}

Table tabulate(Device& device, const TabulateSpec& s, TabulateTiming* timing) {
  const auto t0 = Clock::now();
  if (s.layout == TableLayout::Merl) throw Error("the merl layout is written by tabulate_merl");
  detail::check_tabulate_spec(s);
  const std::vector<int> res = tabulate_resolution(s);
  auto& dev = device.impl();
  const int lanes = detail::resolve_lanes(s.options, dev.info);
  const std::vector<Material> mats = params_of(s);
  const Lobes lobes = s.options.specialize ? lobes_used(s.model, mats) : all_lobes(s.model);
  cl::Program program = detail::build_program(dev, detail::brdf_program_spec(s.model, lobes, s.options, lanes));
  const detail::PackedMaterials packed = detail::pack_materials(s.model, mats);
  Table t = detail::make_tabulate_table(s, res);
  const Precision prec = s.options.precision;
  const std::string what = std::string("kernel brdf_") + table_layout_name(s.layout) + " on '" + dev.info.name + "'";
  const double device_seconds = detail::cl_call(what, [&] {
    cl::Buffer params = detail::brdf_real_buffer(dev, prec, packed.params),
               sheen = detail::brdf_real_buffer(dev, prec, packed.sheen);
    const TabulateLaunch k{dev, s, res, mats, program, params, sheen, lanes};
    return s.layout == TableLayout::Albedo ? tabulate_albedo(k, t) : tabulate_cells(k, t);
  });
  detail::tabulate_metadata(t.metadata, s, res, device_name(dev), precision_label(s.options),
                            lobes_name(s.model, lobes));
  if (s.layout == TableLayout::Albedo)
    t.set_meta("method", "deterministic quadrature over the half vector, split at the horizon (kernels/brdf_eval.cl)");
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = seconds_since(t0);
  }
  return t;
}

}  // namespace brdfbake
