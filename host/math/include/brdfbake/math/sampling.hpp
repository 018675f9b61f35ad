// Low-discrepancy point sets of the sampling estimators (the kernels' common/sampling.clh has the
// device side of the same sequences).
#pragma once

#include <cstdint>

namespace brdfbake::math {

// The base-2 radical inverse (van der Corput): the bits of i mirrored about the binary point, in
// [0, 1) exactly representable in double.
double radical_inverse_base2(std::uint32_t i);

// The k-th of n Hammersley points in [0, 1)^2: ((k + 0.5) / n, radical_inverse_base2(k)) (the
// first coordinate at cell centres, as every table of the project).
struct Point2 {
  double u, v;
};
Point2 hammersley(std::uint32_t k, std::uint32_t n);

}  // namespace brdfbake::math
