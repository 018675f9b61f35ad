#include "brdfbake/reference/quadrature.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace brdfbake::reference {
namespace {

// Geometric refinement: a panel [d, 3d] from the end, i.e. twice as long as its distance to it.
constexpr double kGradingRatio = 3.0;

}  // namespace

void append_panels(double a, double b, const EndRefinement& at_a, const EndRefinement& at_b, double max_width,
                   std::vector<Panel>& out) {
  const double length = b - a;
  if (!(length > 0.0)) return;
  if (!(max_width > 0.0)) throw std::invalid_argument("append_panels: max_width must be positive");

  // Offsets of the graded break points from each end, innermost first.
  const bool both = at_a.refine && at_b.refine;
  const double budget = both ? 0.5 * length : length;
  auto graded_offsets = [&](const EndRefinement& r, double offsets[], int& count) {
    count = 0;
    // The innermost panel obeys max_width like every other.
    const double innermost = std::min(r.min_size, max_width);
    if (!r.refine || !(innermost > 0.0) || innermost >= budget) return;
    double o = innermost;
    offsets[count++] = o;
    while (count < 64) {
      const double next = kGradingRatio * o;
      if (next > budget || next - o > max_width) break;
      o = next;
      offsets[count++] = o;
    }
  };
  double offsets_a[64];
  double offsets_b[64];
  int count_a = 0;
  int count_b = 0;
  graded_offsets(at_a, offsets_a, count_a);
  graded_offsets(at_b, offsets_b, count_b);

  // Break points, ascending.
  double points[64 + 64 + 4096 + 2];
  int n_points = 0;
  points[n_points++] = a;
  for (int k = 0; k < count_a; ++k) points[n_points++] = a + offsets_a[k];
  const double mid_a = count_a > 0 ? a + offsets_a[count_a - 1] : a;
  const double mid_b = count_b > 0 ? b - offsets_b[count_b - 1] : b;
  const double mid_length = mid_b - mid_a;
  if (mid_length > 0.0) {
    const double pieces = std::ceil(mid_length / max_width);
    const int n_mid = pieces > 4096.0 ? 4096 : static_cast<int>(pieces);
    for (int k = 1; k < n_mid; ++k) points[n_points++] = mid_a + mid_length * k / n_mid;
  }
  if (count_b > 0 && mid_length > 0.0) points[n_points++] = mid_b;
  for (int k = count_b - 2; k >= 0; --k) points[n_points++] = b - offsets_b[k];
  points[n_points++] = b;

  const bool map_a = at_a.map_power != 1.0;
  const bool map_b = at_b.map_power != 1.0;
  if (n_points == 2 && map_a && map_b) {
    // One panel cannot carry both maps: halve it.
    const double mid = 0.5 * (a + b);
    out.push_back(Panel{a, mid, at_a.map_power, 1.0});
    out.push_back(Panel{mid, b, 1.0, at_b.map_power});
    return;
  }
  for (int k = 0; k + 1 < n_points; ++k) {
    if (!(points[k + 1] > points[k])) continue;
    Panel panel{points[k], points[k + 1]};
    if (k == 0 && map_a) panel.power_a = at_a.map_power;
    if (k + 2 == n_points && map_b) panel.power_b = at_b.map_power;
    out.push_back(panel);
  }
}

}  // namespace brdfbake::reference
