// Deterministic composite Gauss-Legendre quadrature for the scalar reference.
//
// The Gauss-Legendre rules themselves are the shared maths' (brdfbake/math/gauss_legendre.hpp,
// tested in tests/math). Integrals are sums over panels; a panel may carry a power map at an end
// (t = a + L s^p), which turns an endpoint behaviour such as sqrt(t - a) * smooth into an analytic
// integrand, and intervals can be refined geometrically towards an end where the integrand is
// (nearly) singular.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "brdfbake/math/gauss_legendre.hpp"

namespace brdfbake::reference {

using math::gauss_legendre;
using math::GaussLegendreRule;

// A panel [a, b] of length L. Its Gauss nodes s in [0, 1] are placed at t = a + L s^power_a (when
// power_a != 1) or t = b - L (1 - s)^power_b (when power_b != 1), else linearly. An endpoint
// behaviour (t - a)^q * smooth becomes s^(power_a q) * smooth: analytic when power_a q is an integer
// (power 2 removes a square root), smooth enough for Gauss-Legendre when it is large. At most one of
// the two powers differs from 1.
struct Panel {
  double a;
  double b;
  double power_a = 1.0;
  double power_b = 1.0;
};

// One quadrature node of a panel. `from_a` and `from_b` are t - a and b - t computed without
// cancellation, for integrands that need the distance to a (near-)singular end accurately.
struct PanelNode {
  double t;
  double weight;
  double from_a;
  double from_b;
};

// Calls visit(const PanelNode&) for every node of `rule` mapped onto `panel`.
template <class Visit>
void for_each_node(const Panel& panel, const GaussLegendreRule& rule, Visit&& visit);

// Geometric refinement towards one end of an interval. Panels there are [d, 3d] away from the end
// (a panel twice as long as its distance to the end, so a singularity at the end sits at a fixed
// relative distance and every panel converges at the same geometric rate), down to an innermost
// panel of length `min_size` that touches the end.
struct EndRefinement {
  bool refine = false;     // refine geometrically towards this end
  double min_size = 0.0;   // length of the innermost panel (ignored unless refine)
  double map_power = 1.0;  // power of the map of the panel touching this end (see Panel)
};

// Appends panels covering [a, b] (nothing if b <= a): refined towards a and/or b as asked, the rest
// uniform and no longer than max_width. A lone panel asked for maps at both ends is halved.
void append_panels(double a, double b, const EndRefinement& at_a, const EndRefinement& at_b, double max_width,
                   std::vector<Panel>& out);

// Integral over [a, b] of f with `panels_count` equal linear panels of `rule`; a plain helper for
// tests and smooth one-dimensional integrands.
template <class F>
double integrate_uniform(double a, double b, int panels_count, const GaussLegendreRule& rule, F&& f);

// ---------------------------------------------------------------------------------------------
// Implementation of the templates.

template <class Visit>
void for_each_node(const Panel& panel, const GaussLegendreRule& rule, Visit&& visit) {
  const double length = panel.b - panel.a;
  const std::size_t n = rule.nodes.size();
  for (std::size_t k = 0; k < n; ++k) {
    // s and 1 - s from the symmetric rule, each without cancellation.
    const double s = 0.5 * (1.0 + rule.nodes[k]);
    const double s_bar = 0.5 * (1.0 + rule.nodes[n - 1 - k]);
    const double half_w = 0.5 * rule.weights[k];
    PanelNode node{};
    if (panel.power_a != 1.0) {
      const double p = panel.power_a;
      const double sp = std::pow(s, p);
      node.from_a = length * sp;
      node.from_b = -length * std::expm1(p * std::log(s));  // L (1 - s^p)
      node.weight = length * p * (sp / s) * half_w;
    } else if (panel.power_b != 1.0) {
      const double p = panel.power_b;
      const double sp = std::pow(s_bar, p);
      node.from_b = length * sp;
      node.from_a = -length * std::expm1(p * std::log(s_bar));
      node.weight = length * p * (sp / s_bar) * half_w;
    } else {
      node.from_a = length * s;
      node.from_b = length * s_bar;
      node.weight = length * half_w;
    }
    node.t = node.from_a <= node.from_b ? panel.a + node.from_a : panel.b - node.from_b;
    visit(static_cast<const PanelNode&>(node));
  }
}

template <class F>
double integrate_uniform(double a, double b, int panels_count, const GaussLegendreRule& rule, F&& f) {
  if (panels_count < 1) throw std::invalid_argument("integrate_uniform: panels_count must be positive");
  double sum = 0.0;
  const double width = (b - a) / panels_count;
  for (int p = 0; p < panels_count; ++p) {
    const Panel panel{a + p * width, p + 1 == panels_count ? b : a + (p + 1) * width};
    for_each_node(panel, rule, [&](const PanelNode& node) { sum += node.weight * f(node.t); });
  }
  return sum;
}

}  // namespace brdfbake::reference
