// One name and one definition per table kind's error figure (brdfbake/error_figures.hpp).
#include "brdfbake/error_figures.hpp"

namespace brdfbake {

namespace {

// The stored values of a table against the converged integral: absolute where the value is at most 1,
// relative above it (a DFG table's Charlie albedo reaches 20): the integration bound plus the
// storage's error measured on the stored values (families/delivery.cpp).
constexpr ErrorFigure kBoundMixed{
    "error_bound_mixed",
    "bound on |stored - converged| / max(1, |converged|) over every value the file stores: the integration bound "
    "plus the storage error measured on the stored values"};
// A prefiltered chain: per level, a relative bound on the luminance against the double reference
// (prefilter/bound.cpp), the largest over the levels, plus binary16's relative rounding.
constexpr ErrorFigure kBoundRel{
    "error_bound_rel",
    "bound on |stored - converged| / converged of each texel's luminance: the largest over the levels of "
    "max(2 RMS, max) of the relative differences sampled against the double reference, plus the storage's "
    "relative error"};
// The irradiance SH: what 3 bands (and the window) miss of the exact irradiance of the source.
constexpr ErrorFigure kRmsRel{
    "error_rms_rel",
    "relative RMS of the luminance of the stored irradiance (E / pi) against the exact irradiance of the "
    "source's pixels, over a Fibonacci sphere of directions"};
// A preview: the reference render's own error.
constexpr ErrorFigure kRmsRelBound{
    "error_rms_rel_bound",
    "bound on the relative RMS of the reference render against its converged value, the largest over the "
    "spheres"};

}  // namespace

const ErrorFigure& error_figure(TableKind kind) {
  switch (kind) {
    case TableKind::Prefilter:
      return kBoundRel;
    case TableKind::Irradiance:
      return kRmsRel;
    case TableKind::Preview:
      return kRmsRelBound;
    default:
      return kBoundMixed;
  }
}

std::vector<std::string> error_figure_names() {
  return {kBoundMixed.name, kBoundRel.name, kRmsRel.name, kRmsRelBound.name};
}

std::optional<std::pair<std::string, std::string>> error_figure_value(
    const std::vector<std::pair<std::string, std::string>>& meta) {
  std::vector<std::string> names = error_figure_names();
  names.push_back(kLegacyErrorBoundName);
  for (const std::string& n : names)
    for (const auto& [k, v] : meta)
      if (k == n) return std::make_pair(k, v);
  return std::nullopt;
}

}  // namespace brdfbake
