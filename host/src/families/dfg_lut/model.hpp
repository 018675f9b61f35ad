// Internal: the DFG tables' model, shared by the family's descriptor and its two kernels (opencl.cpp,
// reference.cpp): the table a resolved spec makes (model.cpp) and the calibration of the Monte Carlo
// and quadrature estimators (calibration.cpp).
#pragma once

#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/table.hpp"
#include "enum_names.hpp"

namespace brdfbake::detail {

// The names of the family's enums (model.cpp's *_from_name and *_name read these; the schema offers them).
inline constexpr EnumName<LutKind> kLutKindNames[] = {
    {LutKind::Ggx, "ggx"}, {LutKind::GgxMultiscatter, "ggx-multiscatter"}, {LutKind::Charlie, "charlie"}};
inline constexpr EnumName<Estimator> kEstimatorNames[] = {{Estimator::Quadrature, "quadrature"},
                                                          {Estimator::Vndf, "vndf"},
                                                          {Estimator::Ndf, "ndf"},
                                                          {Estimator::Uniform, "uniform"}};
inline constexpr EnumName<SheenVisibility> kSheenVisibilityNames[] = {{SheenVisibility::EstevezKulla, "estevez-kulla"},
                                                                      {SheenVisibility::Neubelt, "neubelt"}};
inline constexpr EnumName<LutAxis> kLutAxisNames[] = {{LutAxis::Uniform, "uniform"}, {LutAxis::Sqrt, "sqrt"}};

// The table of a resolved spec (resolve_lut_spec): axes, channels and the metadata every DFG table
// carries; the backend fills the data and adds its device, precision, estimator and error bound.
Table make_lut_table(const LutSpec& resolved);

// Evaluations per texel when a spec names neither samples nor max_error: the smallest calibrated
// count whose error is within the default bound (1e-4).
int default_lut_samples(LutKind kind, Estimator estimator, Precision precision);
// The fewest calibrated samples of the spec's kind, estimator and precision whose measured error is
// within spec.max_error; 0 when none is, and then *best_error is the smallest measured (or -1).
int lut_samples_for(const LutSpec& spec, double* best_error);

// The metadata a device table records about its estimator's error bound (error_bound and its
// definition, error_bound_measured_at when the count was not measured itself).
void set_lut_error_bound_meta(Table& t, const LutSpec& resolved);

}  // namespace brdfbake::detail
