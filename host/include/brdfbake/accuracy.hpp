// Accuracy against time of the DFG tables: every estimator over its sample counts, against the
// converged scalar double reference, with device time from OpenCL event profiling. One home for
// the sweep that bench/lut_accuracy (the calibration behind every DFG error bound) and
// `brdfbake report` both run (docs/BENCHMARKS.md).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "brdfbake/device.hpp"
#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

// Max and RMS over every channel and cell of |got - want| / max(1, |want|): absolute below 1,
// relative above (the Charlie albedo exceeds 1 at grazing). The measure of the tests, the
// calibration and the report. Throws Error when the shapes differ.
struct TableErrors {
  double max = 0.0;
  double rms = 0.0;
};
TableErrors table_errors(const Table& got, const Table& want);

// The estimators a kind supports, the default (quadrature) first.
std::vector<Estimator> lut_estimators(LutKind kind);

// Device time of one DFG configuration: `warm_up` untimed bakes (program build, caches), then up to
// `runs` timed bakes; the median device time (event profiling) is returned and the last table put
// in *table. A bake slower than `single_run_above` seconds is timed once.
double lut_device_time(Device& device, const LutSpec& spec, int runs, Table* table, int warm_up = 1,
                       double single_run_above = 1e30);

struct DfgSweepOptions {
  int size = 64;            // the table is size x size
  std::vector<int> counts;  // sample counts; empty: kDfgSweepCounts
  std::vector<Precision> precisions = {Precision::Fp32};
  std::vector<Estimator> estimators;  // empty: every estimator of the kind
  int runs = 3;                       // timed runs of a bake (median), 1 above single_run_above
  double single_run_above = 0.1;      // seconds
  // A bake slower than this skips the larger counts of its estimator and precision (0: none).
  double max_seconds_per_bake = 0.0;
  // Monte Carlo in fp64 above this many samples costs the most and tells the least: skipped.
  int max_monte_carlo_fp64_samples = 4096;
  SheenVisibility sheen_visibility = SheenVisibility::EstevezKulla;
  // The converged reference of this kind and size when the caller has it (e.g. computed on one
  // thread for a timing baseline); nullptr: lut_reference_table on every core.
  const Table* reference = nullptr;
  std::function<void(const std::string&)> log;  // one line per measurement, for progress
};

// The sample counts of the full sweep (bench/lut_accuracy).
inline const std::vector<int> kDfgSweepCounts = {16, 32, 64, 128, 256, 384, 512, 768, 1024, 2048, 4096, 8192, 16384};

struct DfgSweepPoint {
  Estimator estimator = Estimator::Quadrature;
  Precision precision = Precision::Fp32;
  int samples = 0;
  int evaluations_per_texel = 0;  // what the kernel made (the quadrature rounds to its rule)
  double device_seconds = 0.0;
  TableErrors error;  // against the reference
};

struct DfgSweep {
  LutKind kind = LutKind::Ggx;
  int size = 0;
  std::string device;              // the device's name
  double reference_seconds = 0.0;  // wall time of the converged reference table
  int reference_threads = 0;       // 0: the caller gave the reference (not timed here)
  TableErrors reference_error;     // the reference against itself: 0 (the measure's own check)
  std::vector<DfgSweepPoint> points;
  std::vector<std::string> skipped;  // what was not measured, and why
};

// The converged reference table of `kind` at size x size (bake_lut_reference, every core).
Table lut_reference_table(LutKind kind, int size, SheenVisibility visibility, double* seconds);

// Runs the sweep of one kind. Throws Error for a bad size or count.
DfgSweep sweep_dfg(Device& device, LutKind kind, const DfgSweepOptions& options);

}  // namespace brdfbake
