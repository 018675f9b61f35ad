// The DFG accuracy-against-time sweep (brdfbake/accuracy.hpp): bench/lut_accuracy and
// `brdfbake report` both run it, so the calibration and the report measure the same way.
#include "brdfbake/accuracy.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <thread>

#include "brdfbake/error.hpp"

namespace brdfbake {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string fmt(double v, const char* f) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

TableErrors table_errors(const Table& got, const Table& want) {
  if (got.width != want.width || got.height != want.height || got.data.size() != want.data.size())
    throw Error("table_errors: tables of different shapes (" + std::to_string(got.width) + "x" +
                std::to_string(got.height) + " and " + std::to_string(want.width) + "x" + std::to_string(want.height) +
                ")");
  TableErrors e;
  double sum = 0.0;
  for (size_t k = 0; k < got.data.size(); ++k) {
    const double w = want.data[k];
    const double d = std::fabs(double(got.data[k]) - w) / std::max(1.0, std::fabs(w));
    e.max = std::max(e.max, std::isfinite(d) ? d : double(INFINITY));
    sum += d * d;
  }
  e.rms = got.data.empty() ? 0.0 : std::sqrt(sum / double(got.data.size()));
  return e;
}

std::vector<Estimator> lut_estimators(LutKind kind) {
  if (kind == LutKind::Charlie) return {Estimator::Quadrature, Estimator::Ndf, Estimator::Uniform};
  return {Estimator::Quadrature, Estimator::Vndf, Estimator::Ndf};
}

double lut_device_time(Device& device, const LutSpec& spec, int runs, Table* table, int warm_up,
                       double single_run_above) {
  LutTiming t;
  for (int k = 0; k < warm_up; ++k) *table = bake_lut(device, spec, &t);
  std::vector<double> times;
  for (int r = 0; r < std::max(1, runs); ++r) {
    *table = bake_lut(device, spec, &t);
    times.push_back(t.device_seconds);
    if (t.device_seconds > single_run_above) break;
  }
  return median(times);
}

Table lut_reference_table(LutKind kind, int size, SheenVisibility visibility, double* seconds) {
  LutSpec s;
  s.kind = kind;
  s.width = size;
  s.sheen_visibility = visibility;
  const auto t0 = std::chrono::steady_clock::now();
  Table t = bake_lut_reference(s);
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

DfgSweep sweep_dfg(Device& device, LutKind kind, const DfgSweepOptions& o) {
  if (o.size < 1 || o.size > kLutMaxSize) throw Error("sweep: size must be 1 to " + std::to_string(kLutMaxSize));
  const std::vector<int> counts = o.counts.empty() ? kDfgSweepCounts : o.counts;
  for (int n : counts)
    if (n < 1 || n > kLutMaxSamples) throw Error("sweep: sample count " + std::to_string(n) + " is out of range");
  DfgSweep sweep;
  sweep.kind = kind;
  sweep.size = o.size;
  sweep.device = device.info().name;
  sweep.reference_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  auto log = [&](const std::string& line) {
    if (o.log) o.log(line);
  };
  log(std::string(lut_kind_name(kind)) + ": converged reference " + std::to_string(o.size) + "x" +
      std::to_string(o.size));
  Table computed;
  if (!o.reference) computed = lut_reference_table(kind, o.size, o.sheen_visibility, &sweep.reference_seconds);
  const Table& ref = o.reference ? *o.reference : computed;
  if (o.reference) sweep.reference_threads = 0;  // the caller's, not timed here
  sweep.reference_error = table_errors(ref, ref);

  const std::vector<Estimator> supported = lut_estimators(kind);
  const std::vector<Estimator> estimators = o.estimators.empty() ? supported : o.estimators;
  for (Estimator est : estimators) {
    if (std::find(supported.begin(), supported.end(), est) == supported.end()) {
      sweep.skipped.push_back(std::string(estimator_name(est)) + ": not an estimator of " + lut_kind_name(kind));
      continue;
    }
    for (Precision prec : o.precisions) {
      if (prec == Precision::Fp64 && !device.info().fp64) {
        sweep.skipped.push_back(std::string(estimator_name(est)) + " fp64: the device has no fp64");
        continue;
      }
      bool warmed = false, capped = false;
      for (int samples : counts) {
        const std::string what =
            std::string(estimator_name(est)) + " " + precision_name(prec) + " " + std::to_string(samples);
        if (capped) {
          sweep.skipped.push_back(what + ": a smaller count took more than " + fmt(o.max_seconds_per_bake, "%g") +
                                  " s");
          continue;
        }
        if (est != Estimator::Quadrature && prec == Precision::Fp64 && samples > o.max_monte_carlo_fp64_samples) {
          sweep.skipped.push_back(what + ": Monte Carlo in fp64 above " +
                                  std::to_string(o.max_monte_carlo_fp64_samples) + " samples");
          continue;
        }
        LutSpec s;
        s.kind = kind;
        s.width = o.size;
        s.estimator = est;
        s.precision = prec;
        s.samples = samples;
        s.sheen_visibility = o.sheen_visibility;
        Table got;
        // The program is built (or fetched from the cache) once per estimator and precision.
        const double t = lut_device_time(device, s, o.runs, &got, warmed ? 0 : 1, o.single_run_above);
        warmed = true;
        DfgSweepPoint p;
        p.estimator = est;
        p.precision = prec;
        p.samples = samples;
        p.evaluations_per_texel = std::atoi(got.meta("evaluations_per_texel").c_str());
        p.device_seconds = t;
        p.error = table_errors(got, ref);
        sweep.points.push_back(p);
        log("  " + what + " samples: " + fmt(t * 1e3, "%.1f") + " ms, max error " + fmt(p.error.max, "%.2e"));
        if (o.max_seconds_per_bake > 0 && t > o.max_seconds_per_bake) capped = true;
      }
    }
  }
  return sweep;
}

}  // namespace brdfbake
