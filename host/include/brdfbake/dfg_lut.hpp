// The split-sum DFG lookup tables (GGX scale/bias + Burley diffuse, the multiple-scattering form,
// and the Charlie sheen albedo), baked on any backend, an OpenCL device or by the scalar reference
// (the family dfg_lut: host/src/families/dfg_lut/, kernels/dfg_lut.cl, host/reference/src/dfg_lut.cpp).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "brdfbake/device.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

enum class LutKind { Ggx, GgxMultiscatter, Charlie };
LutKind lut_kind_from_name(const std::string& name);  // "ggx" | "ggx-multiscatter" | "charlie"
const char* lut_kind_name(LutKind kind);

// How the lobe integral of each texel is estimated.
enum class Estimator {
  Quadrature,  // deterministic Gauss-Legendre in the lobe's CDF variables, split at the horizon
  Vndf,        // Monte Carlo, GGX visible normals (Heitz 2018), Hammersley points
  Ndf,         // Monte Carlo, the distribution of normals (GGX or Charlie), Hammersley points
  Uniform,     // Monte Carlo, uniform hemisphere (Charlie only)
};
Estimator estimator_from_name(const std::string& name);  // "quadrature" | "vndf" | "ndf" | "uniform"
const char* estimator_name(Estimator e);

// How a table axis maps cells to the quantity: uniform, texel i at x = (i + 0.5) / N (the lookup
// uv is the quantity itself); sqrt, x = ((i + 0.5) / N)^2 (the lookup uv is sqrt of the quantity),
// which puts more texels where the integrals change fastest (grazing n_dot_v, low roughness).
enum class LutAxis { Uniform, Sqrt };
LutAxis lut_axis_from_name(const std::string& name);  // "uniform" | "sqrt"
const char* lut_axis_name(LutAxis axis);
// The lookup coordinate of a quantity and back (the shader's formula is in the table's metadata).
double lut_axis_uv(LutAxis axis, double x);
double lut_axis_value(LutAxis axis, double uv);

enum class SheenVisibility { EstevezKulla, Neubelt };
SheenVisibility sheen_visibility_from_name(const std::string& name);  // "estevez-kulla" | "neubelt"
const char* sheen_visibility_name(SheenVisibility v);

// Limits: the largest table side, the most evaluations per texel of the Monte Carlo estimators and
// of the quadrature (its longest rule: 512 polar x 32 azimuthal nodes on each of two panels), and
// the convergence the scalar reference states (tests/reference).
inline constexpr int kLutMaxSize = 16384;
inline constexpr int kLutMaxSamples = 1 << 20;
inline constexpr int kLutMaxQuadratureSamples = 2 * 512 * 32;
inline constexpr double kLutReferenceBound = 1e-6;
// The most texels of a table (8192 x 8192), and the most evaluations of a whole bake (texels x
// evaluations per texel, 2^40: about a minute on a discrete GPU, hours on a CPU device), so that no
// request runs unbounded (docs/RELIABILITY.md, "Limits").
inline constexpr long long kLutMaxTexels = 1ll << 26;
inline constexpr double kLutMaxEvaluations = 1099511627776.0;

struct LutSpec {
  LutKind kind = LutKind::Ggx;
  int width = 128;         // cells along n_dot_v
  int height = 0;          // cells along roughness; 0: same as width
  int samples = 0;         // evaluations per texel; 0: the default (or from max_error)
  double max_error = 0.0;  // > 0: the fewest samples whose measured max error is below it
  Estimator estimator = Estimator::Quadrature;
  Precision precision = Precision::Fp32;
  SheenVisibility sheen_visibility = SheenVisibility::EstevezKulla;
  LutAxis n_dot_v_axis = LutAxis::Uniform;
  LutAxis roughness_axis = LutAxis::Uniform;
  // When non-empty, evaluate at these coordinates instead of the cell centres (tests, corners).
  std::vector<double> n_dot_v;
  std::vector<double> roughness;
};

// Throws Error for sizes < 1 or too large, negative samples, NaN bounds, and estimators the kind
// does not support. Fills the defaults (height, samples) in the returned copy.
LutSpec resolve_lut_spec(const LutSpec& spec);

// The channel names of a kind, in order.
std::vector<std::string> lut_channels(LutKind kind);

struct LutTiming {
  double device_seconds = 0.0;  // kernel time from OpenCL event profiling
  double wall_seconds = 0.0;    // the whole call, program build included
};

// Called with the fraction done (0..1) as rows of the table complete.
using Progress = std::function<void(double)>;

class Backend;

// Bakes on a backend (brdfbake/backend.hpp): its OpenCL device or the scalar reference.
Table bake_lut(Backend& backend, const LutSpec& spec, LutTiming* timing = nullptr, const Progress& progress = {});
// Bakes on an OpenCL device.
Table bake_lut(Device& device, const LutSpec& spec, LutTiming* timing = nullptr, const Progress& progress = {});
// Bakes with the converged scalar double reference (spec.samples and estimator are ignored).
Table bake_lut_reference(const LutSpec& spec, LutTiming* timing = nullptr, const Progress& progress = {});

// The measured max error (abs below 1, relative above; over every channel of the 128x128 table,
// against the converged reference, plus a 25% margin) of an estimator at a sample count, from the
// calibration that bench/lut_accuracy measures (docs/BENCHMARKS.md). For a count that was not
// measured, the bound of the largest measured count below it, and *measured_at says which count
// that was; a negative value when none is known.
double lut_error_bound(LutKind kind, Estimator estimator, Precision precision, int samples, int* measured_at = nullptr);

}  // namespace brdfbake
