// The automatic exposure of a picture of radiance (view/exposure.hpp).
#include "view/exposure.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace brdfbake::view {

double auto_exposure(const float* rgb, size_t texels, size_t stride) {
  std::vector<double> lum;
  lum.reserve(texels);
  for (size_t t = 0; t < texels; ++t) {
    const float* p = rgb + t * stride;
    const double y = 0.2126 * double(p[0]) + 0.7152 * double(p[1]) + 0.0722 * double(p[2]);
    if (std::isfinite(y) && y >= 0) lum.push_back(y);
  }
  if (lum.empty()) return 0.0;
  const size_t k = (lum.size() - 1) * 99 / 100;
  std::nth_element(lum.begin(), lum.begin() + std::ptrdiff_t(k), lum.end());
  const double p99 = lum[k];
  if (!(p99 > 0)) return 0.0;
  double log_sum = 0;
  for (double y : lum) log_sum += std::log(std::max(y, 1e-4 * p99));
  const double log_average = std::exp(log_sum / double(lum.size()));
  const double ev = std::min(std::log2(kAutoExposureKey / log_average), std::log2(kAutoExposureWhite / p99));
  return std::clamp(std::floor(10.0 * ev) / 10.0, -kAutoExposureLimit, kAutoExposureLimit);
}

}  // namespace brdfbake::view
