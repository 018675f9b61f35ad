// The report's page: one self-contained HTML file, its plots inline SVG drawn here (text stays text,
// scales without blur, and nothing is fetched from the network), the numbers in tables beside them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

#include "brdfbake/report.hpp"

namespace brdfbake {

namespace {

std::string fmt(double v, const char* f = "%.3g") {
  if (!std::isfinite(v)) return "inf";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '&')
      o += "&amp;";
    else if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '"')
      o += "&quot;";
    else
      o += c;
  }
  return o;
}

const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"};

struct Series {
  std::string name;
  std::vector<double> x, y;
  std::vector<std::string> labels;  // one per point, may be empty (each also in the point's hover title)
  // Per point, whether its label is written beside it (empty: Always). Always labels are placed first
  // (where they cover the least); IfRoom ones then only where they cover nothing.
  enum class Label { Always, IfRoom, Never };
  std::vector<Label> label_modes;
  Label label_mode(size_t i) const { return i < label_modes.size() ? label_modes[i] : Label::Always; }
  bool dashed = false;
  bool line = true;  // join the points (a sweep); false: markers only
};

// An axis: log10 over whole decades, or linear over [lo, hi] with round ticks.
struct Axis {
  bool log = true;
  bool tight = false;  // log: the data's own range (a margin of 5 %) with 1-2-5 ticks, not whole decades
  double lo = 0, hi = 1;
  double map(double v, double a, double b) const {  // to pixels a..b
    const double t = log ? (std::log10(v) - lo) / (hi - lo) : (v - lo) / (hi - lo);
    return a + t * (b - a);
  }
  std::vector<std::pair<double, std::string>> ticks() const {
    std::vector<std::pair<double, std::string>> t;
    if (log && tight) {
      // Mantissas at 1, 1.5, 2, 3, 5, 7 of each decade inside the range; finer (every 0.5, then every
      // 0.1) while that gives fewer than 3 ticks; thinned to at most 8.
      std::vector<double> all;
      for (double step : {0.0, 0.5, 0.1}) {
        std::vector<double> mantissas = {1.0, 1.5, 2.0, 3.0, 5.0, 7.0};
        if (step > 0) {
          mantissas.clear();
          for (double m = 1.0; m < 9.99; m += step) mantissas.push_back(m);
        }
        all.clear();
        for (int e = static_cast<int>(std::floor(lo)); e <= static_cast<int>(std::ceil(hi)); ++e)
          for (double m : mantissas) {
            const double v = m * std::pow(10.0, e);
            if (std::log10(v) >= lo && std::log10(v) <= hi) all.push_back(v);
          }
        if (all.size() >= 3) break;
      }
      const size_t stride = (all.size() + 7) / 8;
      for (size_t k = 0; k < all.size(); k += std::max<size_t>(1, stride)) t.push_back({all[k], fmt(all[k], "%g")});
    } else if (log) {
      const int step = std::max(1, static_cast<int>(std::ceil((hi - lo) / 8)));
      for (int e = static_cast<int>(lo); e <= static_cast<int>(hi); e += step)
        t.push_back({std::pow(10.0, e), "1e" + std::to_string(e)});
    } else {
      const double span = hi - lo, raw = span / 5;
      const double mag = std::pow(10.0, std::floor(std::log10(raw)));
      const double step = raw / mag < 2 ? 2 * mag : raw / mag < 5 ? 5 * mag : 10 * mag;
      for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step) t.push_back({v, fmt(v, "%g")});
    }
    return t;
  }
};

Axis make_axis(const std::vector<Series>& s, bool x, bool log, bool tight = false) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& ser : s)
    for (double v : x ? ser.x : ser.y) {
      if (!std::isfinite(v) || (log && v <= 0)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  Axis a;
  a.log = log;
  if (!(lo <= hi)) {
    lo = log ? 1e-3 : 0;
    hi = log ? 1 : 1;
  }
  if (log && tight) {
    const double l = std::log10(lo), h = std::log10(hi), margin = std::max(0.05 * (h - l), 0.02);
    a.tight = true;
    a.lo = l - margin;
    a.hi = h + margin;
  } else if (log) {
    a.lo = std::floor(std::log10(lo));
    a.hi = std::ceil(std::log10(hi));
    if (a.hi <= a.lo) a.hi = a.lo + 1;
  } else {
    a.lo = std::min(0.0, lo);
    a.hi = hi > a.lo ? hi * 1.05 : a.lo + 1;
  }
  return a;
}

// Where the labels beside the points go: for each label the first of a few places around its point
// (right and above first; then below, left, further out) that covers no other label, no point and
// stays inside the plot; where none is free, the place that covers the least, or none (`if_free`).
// Widths are estimated (the 9-pixel sans-serif font: about 5.2 pixels a character).
class LabelPlacer {
 public:
  LabelPlacer(double x0, double y0, double x1, double y1) : x0_(x0), y0_(y0), x1_(x1), y1_(y1) {}
  void add_point(double px, double py) { taken_.push_back({px - 3, py - 3, px + 3, py + 3}); }
  // The label's anchor (x, y) and whether it ends there (text-anchor end) rather than starts.
  struct Place {
    double x, y;
    bool end;
  };
  std::optional<Place> place(double px, double py, const std::string& text, bool if_free) {
    const double w = 5.2 * double(text.size()), h = 9;
    static const double kOffsets[][2] = {{4, -4}, {4, 11}, {-4, -4}, {-4, 11}, {4, -14}, {4, 21}, {-4, -14}, {-4, 21}};
    Place best{px + 4, py - 4, false};
    Box best_box{};
    double best_cover = HUGE_VAL;
    for (const auto& o : kOffsets) {
      const bool end = o[0] < 0;
      const double x = px + o[0], y = py + o[1];
      const Box b{end ? x - w : x, y - h + 1, end ? x : x + w, y + 2};
      double cover = 0;
      for (const Box& t : taken_) cover += overlap(b, t);
      if (b.x0 < x0_ || b.x1 > x1_ || b.y0 < y1_ || b.y1 > y0_) cover += w * h;  // outside the plot
      if (cover < best_cover) {
        best_cover = cover;
        best = {x, y, end};
        best_box = b;
      }
      if (cover == 0) break;
    }
    if (if_free && best_cover > 0) return std::nullopt;
    taken_.push_back(best_box);
    return best;
  }

 private:
  struct Box {
    double x0, y0, x1, y1;
  };
  static double overlap(const Box& a, const Box& b) {
    const double w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0), h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
    return w > 0 && h > 0 ? w * h : 0;
  }
  double x0_, y0_, x1_, y1_;  // the plot's frame: left, bottom, right, top (pixels)
  std::vector<Box> taken_;
};

std::string svg_plot(const std::string& title, const std::string& xlabel, const std::string& ylabel,
                     const std::vector<Series>& series, bool logx, bool logy, bool tight = false) {
  const int w = 620, h = 380, left = 70, right = 150, top = 30, bottom = 50;
  const Axis ax = make_axis(series, true, logx, tight), ay = make_axis(series, false, logy, tight);
  const double x0 = left, x1 = w - right, y0 = h - bottom, y1 = top;
  std::ostringstream o;
  // Styles are attributes, not CSS: the SVG stands alone when saved from the page.
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h << "\" viewBox=\"0 0 " << w
    << ' ' << h << "\" role=\"img\" aria-label=\"" << esc(title)
    << "\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#333\">\n";
  o << "<rect x=\"0\" y=\"0\" width=\"" << w << "\" height=\"" << h << "\" fill=\"#fff\"/>\n";
  o << "<text x=\"" << left << "\" y=\"18\" font-size=\"13\" font-weight=\"bold\">" << esc(title) << "</text>\n";
  for (const auto& [v, label] : ax.ticks()) {
    const double px = ax.map(v, x0, x1);
    o << "<line x1=\"" << px << "\" y1=\"" << y0 << "\" x2=\"" << px << "\" y2=\"" << y1 << "\" stroke=\"#e4e4e4\"/>";
    o << "<text x=\"" << px << "\" y=\"" << y0 + 16 << "\" text-anchor=\"middle\">" << esc(label) << "</text>\n";
  }
  for (const auto& [v, label] : ay.ticks()) {
    const double py = ay.map(v, y0, y1);
    o << "<line x1=\"" << x0 << "\" y1=\"" << py << "\" x2=\"" << x1 << "\" y2=\"" << py << "\" stroke=\"#e4e4e4\"/>";
    o << "<text x=\"" << x0 - 6 << "\" y=\"" << py + 4 << "\" text-anchor=\"end\">" << esc(label) << "</text>\n";
  }
  o << "<rect x=\"" << x0 << "\" y=\"" << y1 << "\" width=\"" << x1 - x0 << "\" height=\"" << y0 - y1
    << "\" fill=\"none\" stroke=\"#999\"/>\n";
  o << "<text x=\"" << (x0 + x1) / 2 << "\" y=\"" << h - 12 << "\" text-anchor=\"middle\">" << esc(xlabel)
    << "</text>\n";
  o << "<text transform=\"translate(16 " << (y0 + y1) / 2 << ") rotate(-90)\" text-anchor=\"middle\">" << esc(ylabel)
    << "</text>\n";
  const auto drawable = [&](const Series& s, size_t i) {
    return std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && !(logx && s.x[i] <= 0) && !(logy && s.y[i] <= 0);
  };
  // The labels' places, before anything is drawn: every point first, then the Always labels, then
  // the IfRoom ones where there is room.
  LabelPlacer placer(x0, y0, x1, y1);
  std::vector<std::vector<std::optional<LabelPlacer::Place>>> places(series.size());
  for (const Series& s : series)
    for (size_t i = 0; i < s.x.size(); ++i)
      if (drawable(s, i)) placer.add_point(ax.map(s.x[i], x0, x1), ay.map(s.y[i], y0, y1));
  for (const Series::Label pass : {Series::Label::Always, Series::Label::IfRoom})
    for (size_t k = 0; k < series.size(); ++k) {
      const Series& s = series[k];
      places[k].resize(s.x.size());
      for (size_t i = 0; i < s.x.size() && i < s.labels.size(); ++i)
        if (drawable(s, i) && !s.labels[i].empty() && s.label_mode(i) == pass)
          places[k][i] =
              placer.place(ax.map(s.x[i], x0, x1), ay.map(s.y[i], y0, y1), s.labels[i], pass == Series::Label::IfRoom);
    }
  for (size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    const char* c = kColours[k % std::size(kColours)];
    std::string path;
    std::ostringstream marks;
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!drawable(s, i)) continue;
      const double px = ax.map(s.x[i], x0, x1), py = ay.map(s.y[i], y0, y1);
      path += (path.empty() ? "M" : " L") + fmt(px, "%.1f") + " " + fmt(py, "%.1f");
      marks << "<circle cx=\"" << fmt(px, "%.1f") << "\" cy=\"" << fmt(py, "%.1f") << "\" r=\"3\" fill=\"" << c
            << "\"><title>" << esc(s.name) << (i < s.labels.size() ? ", " + esc(s.labels[i]) : std::string()) << ": "
            << fmt(s.x[i]) << ", " << fmt(s.y[i]) << "</title></circle>";
      if (const auto& at = places[k][i])  // a white halo keeps it legible over lines
        marks << "<text x=\"" << fmt(at->x, "%.1f") << "\" y=\"" << fmt(at->y, "%.1f") << "\""
              << (at->end ? " text-anchor=\"end\"" : "") << " font-size=\"9\" fill=\"" << c
              << "\" stroke=\"#fff\" stroke-width=\"2.5\" paint-order=\"stroke\">" << esc(s.labels[i]) << "</text>";
      marks << "\n";
    }
    if (!path.empty() && s.line)
      o << "<path d=\"" << path << "\" fill=\"none\" stroke=\"" << c << "\" stroke-width=\"1.5\""
        << (s.dashed ? " stroke-dasharray=\"5 3\"" : "") << "/>\n";
    o << marks.str();
    const double ly = top + 14 + 18 * double(k);
    o << "<line x1=\"" << x1 + 10 << "\" y1=\"" << ly - 4 << "\" x2=\"" << x1 + 30 << "\" y2=\"" << ly - 4
      << "\" stroke=\"" << c << "\" stroke-width=\"2\"" << (s.dashed ? " stroke-dasharray=\"5 3\"" : "")
      << (s.line ? "" : " opacity=\"0\"") << "/><circle cx=\"" << x1 + 20 << "\" cy=\"" << ly - 4
      << "\" r=\"3\" fill=\"" << c << "\"/>";
    o << "<text x=\"" << x1 + 34 << "\" y=\"" << ly << "\">" << esc(s.name) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

const char* kStyle = R"(
body { font: 14px/1.45 system-ui, sans-serif; margin: 2em auto; max-width: 1300px; color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; } h2 { margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 1em 0; font-variant-numeric: tabular-nums; }
td, th { border: 1px solid #ddd; padding: 3px 8px; text-align: right; } th { background: #f4f4f4; }
td:first-child, th:first-child { text-align: left; }
.meta { color: #555; } .note { color: #555; font-size: 0.92em; }
.plots { display: flex; flex-wrap: wrap; gap: 1em; }
code { background: #f4f4f4; padding: 0 3px; }
)";

std::string load_text(const double l[3]) {
  if (l[0] < 0) return "unknown";
  return fmt(l[0], "%.2f") + " / " + fmt(l[1], "%.2f") + " / " + fmt(l[2], "%.2f");
}

void dfg_section(std::ostringstream& o, const DfgSweep& s) {
  o << "<h2>DFG <code>" << lut_kind_name(s.kind) << "</code>, " << s.size << "&times;" << s.size << "</h2>\n";
  o << "<p>Converged scalar double reference: " << fmt(s.reference_seconds, "%.2f") << " s on " << s.reference_threads
    << " thread" << (s.reference_threads == 1 ? "" : "s")
    << " (its error against itself: " << fmt(s.reference_error.max)
    << "). Each point is one table baked on the device at one sample count; the label is the sample count.</p>\n";
  // Series per estimator and precision.
  std::map<std::string, Series> by;
  std::vector<std::string> order;
  for (const auto& p : s.points) {
    const std::string key = std::string(estimator_name(p.estimator)) + " " + precision_name(p.precision);
    if (!by.count(key)) {
      order.push_back(key);
      by[key].name = key;
      by[key].dashed = p.precision == Precision::Fp64;
    }
    by[key].x.push_back(p.device_seconds * 1e3);
    by[key].y.push_back(p.error.max);
    by[key].labels.push_back(std::to_string(p.samples));
  }
  std::vector<Series> vs_time, vs_samples;
  for (const auto& k : order) {
    vs_time.push_back(by[k]);
    Series n = by[k];
    n.x.clear();
    n.labels.clear();
    for (const auto& p : s.points)
      if (std::string(estimator_name(p.estimator)) + " " + precision_name(p.precision) == k) n.x.push_back(p.samples);
    vs_samples.push_back(n);
  }
  o << "<div class=\"plots\">\n"
    << svg_plot(std::string(lut_kind_name(s.kind)) + ": max error against device time", "device time (ms)",
                "max error vs reference", vs_time, true, true)
    << svg_plot(std::string(lut_kind_name(s.kind)) + ": max error against samples", "samples per texel",
                "max error vs reference", vs_samples, true, true)
    << "</div>\n";
  o << "<table><tr><th>estimator</th><th>precision</th><th>samples</th><th>evaluations/texel</th><th>device time "
       "(ms)</th>"
       "<th>max error</th><th>RMS error</th></tr>\n";
  for (const auto& p : s.points)
    o << "<tr><td>" << estimator_name(p.estimator) << "</td><td>" << precision_name(p.precision) << "</td><td>"
      << p.samples << "</td><td>" << p.evaluations_per_texel << "</td><td>" << fmt(p.device_seconds * 1e3, "%.2f")
      << "</td><td>" << fmt(p.error.max, "%.2e") << "</td><td>" << fmt(p.error.rms, "%.2e") << "</td></tr>\n";
  o << "</table>\n";
  if (!s.skipped.empty()) {
    o << "<p class=\"note\">Not measured: ";
    for (size_t k = 0; k < s.skipped.size(); ++k) o << (k ? "; " : "") << esc(s.skipped[k]);
    o << ".</p>\n";
  }
}

void fresnel_section(std::ostringstream& o, const std::vector<FresnelComparison>& all) {
  o << "<h2>Fresnel models against the exact equations</h2>\n<p>For each measured material, every model set from it "
       "(how is in the table) against the exact conductor or dielectric: the largest |model &minus; exact| over "
       "cos&theta; "
       "in [0, 1] and the three channels, and the device's rate for a 1-D RGB table.</p>\n";
  std::vector<Series> pts;
  for (const auto& c : all) {
    Series s;
    s.name = c.material;
    s.line = false;
    for (const auto& r : c.rows) {
      if (r.cells_per_second <= 0) continue;
      s.x.push_back(1e9 / r.cells_per_second);
      s.y.push_back(r.worst);
      s.labels.push_back(fresnel_model_name(r.model));
    }
    pts.push_back(s);
  }
  if (!all.empty() && all.front().rate_cells > 0)
    o << "<div class=\"plots\">"
      << svg_plot("worst error against device time per cell (the exact model: 0, not drawn)", "device ns per RGB cell",
                  "max |model - exact|", pts, false, true)
      << "</div>\n";
  for (const auto& c : all) {
    o << "<h3>" << esc(c.material) << " (exact: " << fresnel_model_name(c.exact_model) << ")</h3>\n"
      << "<table><tr><th>model</th><th>set from the material</th><th>max error r, g, b</th><th>worst</th><th>at "
         "cos&theta;</th>"
         "<th>device ns/cell</th></tr>\n";
    for (const auto& r : c.rows)
      o << "<tr><td>" << fresnel_model_name(r.model) << "</td><td>" << esc(r.setting) << "</td><td>"
        << fmt(r.max_abs.r, "%.2e") << ", " << fmt(r.max_abs.g, "%.2e") << ", " << fmt(r.max_abs.b, "%.2e")
        << "</td><td>" << fmt(r.worst, "%.2e") << "</td><td>" << fmt(r.cos_at_worst, "%.3f") << "</td><td>"
        << (r.cells_per_second > 0 ? fmt(1e9 / r.cells_per_second, "%.3f") : std::string("&ndash;")) << "</td></tr>\n";
    o << "</table>\n";
  }
}

void prefilter_section(std::ostringstream& o, const std::vector<PrefilterReport>& all) {
  if (all.empty()) return;
  o << "<h2>Prefiltered GGX levels</h2>\n<p>A chain of " << all.front().size << "&sup2; ("
    << esc(all.front().environment)
    << "), each estimator at its default settings, against the brute-force reference filtering the same source cube, "
       "at up "
       "to 8&times;8 texels per face of every level. Error: per channel |P &minus; P<sub>ref</sub>| / "
       "max(P<sub>ref</sub>, "
       "10<sup>&minus;3</sup> mean).</p>\n";
  std::vector<Series> err, time;
  for (const auto& p : all) {
    Series e, t;
    e.name = t.name = p.estimator;
    for (const auto& l : p.levels) {
      e.x.push_back(l.roughness);
      e.y.push_back(l.rms_error);
      t.x.push_back(l.roughness);
      t.y.push_back(l.device_seconds * 1e3);
    }
    err.push_back(e);
    time.push_back(t);
  }
  o << "<div class=\"plots\">"
    << svg_plot("RMS error per level", "roughness of the level", "RMS relative error", err, false, true)
    << svg_plot("device time per level", "roughness of the level", "device time (ms)", time, false, true) << "</div>\n";
  o << "<table><tr><th>estimator</th><th>level</th><th>size</th><th>roughness</th><th>samples</th><th>device time "
       "(ms)</th>"
       "<th>RMS error</th><th>max error</th></tr>\n";
  for (const auto& p : all)
    for (const auto& l : p.levels)
      o << "<tr><td>" << p.estimator << "</td><td>" << l.level << "</td><td>" << l.size << "</td><td>"
        << fmt(l.roughness, "%.3f") << "</td><td>" << (l.samples ? std::to_string(l.samples) : std::string("&ndash;"))
        << "</td><td>" << fmt(l.device_seconds * 1e3, "%.2f") << "</td><td>" << fmt(l.rms_error, "%.2e") << "</td><td>"
        << fmt(l.max_error, "%.2e") << "</td></tr>\n";
  o << "</table>\n";
}

std::string pct(double v) { return fmt(100.0 * v, v < 0.01 ? "%.2f%%" : "%.1f%%"); }
std::string megabytes(std::uint64_t b) { return fmt(double(b) / 1e6, b < 10000000 ? "%.2f MB" : "%.1f MB"); }

// Error against a cost, one series of every setting (markers) and the Pareto front (the points not
// dominated, joined in order of cost). Labels: every point of the front, then the other settings
// where a label has room (each point's setting is also in its hover title and in the table below).
std::string bake_plot(const BakeSweepTarget& t, bool bytes) {
  Series all, front;
  all.name = "settings";
  all.line = false;
  front.name = "Pareto front";
  front.dashed = true;
  std::vector<const BakeSweepPoint*> f;
  auto cost = [&](const BakeSweepPoint& p) { return bytes ? double(p.bytes) / 1e6 : p.seconds; };
  for (const auto& p : t.points) {
    all.x.push_back(cost(p));
    all.y.push_back(p.bake_error);
    all.labels.push_back(p.label);
    const bool pareto = bytes ? p.pareto_bytes : p.pareto_time;
    all.label_modes.push_back(pareto ? Series::Label::Never : Series::Label::IfRoom);  // the front's label
    if (pareto) f.push_back(&p);
  }
  std::sort(f.begin(), f.end(), [&](const BakeSweepPoint* a, const BakeSweepPoint* b) { return cost(*a) < cost(*b); });
  for (const BakeSweepPoint* p : f) {
    front.x.push_back(cost(*p));
    front.y.push_back(p->bake_error);
    front.labels.push_back(p->label);
  }
  return svg_plot(t.target + ": the bake's share against " + (bytes ? "bytes" : "bake time"),
                  bytes ? "bytes written (MB)" : "whole bake, wall seconds",
                  "bake share, median sphere RMS (files vs ideal)", {all, front}, true, true, true);
}

// The worst over a point's groups of their worst sphere's bake share, and of their probe.
double worst_bake(const BakeSweepPoint& p) {
  double w = 0.0;
  for (const auto& g : p.groups) w = std::max(w, g.bake_worst);
  return w;
}
std::string worst_sharp(const BakeSweepPoint& p) {
  double w = -1.0;
  for (const auto& g : p.groups) w = std::max(w, g.sharp);
  return w < 0.0 ? "&ndash;" : pct(w);
}
std::string seconds_text(const BakeSweepPoint& p) {
  return fmt(p.seconds, "%.2f") + (p.wall_seconds.size() > 1 ? " &plusmn; " + fmt(0.5 * p.spread, "%.2f") : "");
}

void bake_section(std::ostringstream& o, const BakeSweep& s) {
  o << "<h2>What each bake setting costs, at the level of the render</h2>\n";
  o << "<p>Environment <code>" << esc(s.environment) << "</code>. For each target, its default bake and one setting "
    << "changed at a time, each baked as <code>brdfbake bake --target T --OPTION VALUE</code> runs it (wall seconds of "
       "the whole bake with the programs cached; the settings the recommendation may take timed 3 times: the median "
       "&plusmn; half the spread; bytes: every file written) and rendered by the target's split-sum shader "
       "(<code>brdfbake preview</code>, the default grid at "
    << s.preview_width << "&times;" << s.preview_width / 2
    << ") against the converged reference render (once per target). The render's error splits in two "
       "(docs/PREVIEW.md): the <b>engine's share</b>, the target's split-sum approximation rendered from an ideal "
       "bake (converged chain levels at the engine's roughness per level, exact DFG values, no storage), which no "
       "setting changes, and the <b>bake's share</b>, the files' render against the ideal bake's: what a setting "
       "buys. Sharp reflections: each group's spheres below roughness 0.1 drawn again where one texel of level 0 "
       "spans 2 pixels (the bake's share there; a 20-pixel sphere cannot show a chain's resolution). "
       "<b>Recommended</b>: of the settings no blurrier than the default (sharp reflections within "
    << fmt((kBakeSharpWithin - 1) * 100, "%.0f")
    << "% of the default's on every group) and read no worse by the engine (each group's engine share within as "
       "much of the default's: a chain of another level count changes the engine's lookup), those whose bake share on "
       "every group's worst sphere is within "
    << fmt((kBakeRecommendWithin - 1) * 100, "%.0f")
    << "% of the best of them for the group, the fastest; settings whose times differ by less than their spread tie, "
       "and the tie goes to the fewest bytes. The sweep took "
    << fmt(s.seconds, "%.0f") << " s.</p>\n";
  o << "<table><tr><th>target</th><th>recommended</th><th>bake (s)</th><th>bytes</th><th>bake share (worst "
       "sphere)</th><th>sharp</th><th>error</th><th>default: bake (s)</th><th>bytes</th><th>bake share (worst "
       "sphere)</th><th>sharp</th><th>error</th><th>engine share</th><th>why</th></tr>\n";
  for (const auto& t : s.targets) {
    if (t.points.empty()) continue;
    const BakeSweepPoint& d = t.points.front();
    o << "<tr><td>" << esc(t.target) << "</td>";
    if (t.recommended >= 0) {
      const BakeSweepPoint& r = t.points[size_t(t.recommended)];
      o << "<td><b>" << esc(r.label) << "</b></td><td>" << seconds_text(r) << "</td><td>" << megabytes(r.bytes)
        << "</td><td>" << pct(r.bake_error) << " (" << pct(worst_bake(r)) << ")</td><td>" << worst_sharp(r)
        << "</td><td>" << pct(r.error) << "</td>";
    } else {
      o << "<td>&ndash;</td><td></td><td></td><td></td><td></td><td></td>";
    }
    o << "<td>" << seconds_text(d) << "</td><td>" << megabytes(d.bytes) << "</td><td>" << pct(d.bake_error) << " ("
      << pct(worst_bake(d)) << ")</td><td>" << worst_sharp(d) << "</td><td>" << pct(d.error) << "</td><td>"
      << pct(d.engine_error) << "</td><td>" << esc(t.why) << "</td></tr>\n";
  }
  o << "</table>\n";
  o << "<p class=\"note\">Bake share and error: the median over the 72 spheres of each sphere's relative RMS (the "
       "worst "
       "sphere of any group in brackets); sharp: the worst group's probe; engine share: the default's median (it "
       "changes only with the chain's level count).</p>\n";
  for (const auto& t : s.targets) {
    if (t.points.empty()) continue;
    o << "<h3>" << esc(t.target) << "</h3>\n<div class=\"plots\">" << bake_plot(t, false) << bake_plot(t, true)
      << "</div>\n";
    o << "<p class=\"note\">Labelled in the plots: every setting on the Pareto front (in its colour), and the "
         "others where their label has room; every point's setting is in its hover title and in the table. "
         "Reference render: "
      << fmt(t.reference_seconds, "%.1f")
      << " s; its own bound (worst sphere, relative RMS): " << pct(t.reference_bound)
      << ". Group columns: the bake's share, the median sphere RMS over the row's 12 roughnesses (the worst in "
         "brackets), and the probe of its sharp reflections after the slash. Recommendation: "
      << esc(t.why) << ".</p>\n";
    o << "<table><tr><th>setting</th><th>bake (s)</th><th>runs</th><th>bytes</th><th>files</th><th>error</th>"
         "<th>engine share</th><th>bake share</th>";
    if (!t.points.front().groups.empty())
      for (const auto& g : t.points.front().groups) o << "<th>" << esc(g.name) << "</th>";
    o << "<th>eligible</th><th>Pareto (time, bytes)</th></tr>\n";
    for (size_t i = 0; i < t.points.size(); ++i) {
      const BakeSweepPoint& p = t.points[i];
      o << "<tr><td>" << (int(i) == t.recommended ? "<b>" + esc(p.label) + "</b> (recommended)" : esc(p.label))
        << "</td><td>" << seconds_text(p) << "</td><td>" << p.wall_seconds.size() << "</td><td>" << megabytes(p.bytes)
        << "</td><td>" << p.files << "</td><td>" << pct(p.error) << "</td><td>" << pct(p.engine_error) << "</td><td>"
        << pct(p.bake_error) << "</td>";
      for (const auto& g : p.groups)
        o << "<td>" << pct(g.bake_median) << " (" << pct(g.bake_worst) << ")"
          << (g.sharp >= 0.0 ? " / " + pct(g.sharp) : std::string()) << "</td>";
      o << "<td>" << (p.eligible ? "yes" : "") << "</td><td>" << (p.pareto_time ? "time" : "")
        << (p.pareto_time && p.pareto_bytes ? ", " : "") << (p.pareto_bytes ? "bytes" : "") << "</td></tr>\n";
    }
    o << "</table>\n";
    if (!t.skipped.empty()) {
      o << "<p class=\"note\">Not baked: ";
      for (size_t k = 0; k < t.skipped.size(); ++k) o << (k ? "; " : "") << esc(t.skipped[k]);
      o << ".</p>\n";
    }
  }
}

// The roofline: the device's measured peaks (fp32, and fp64 dashed) as attainable GFLOP/s against
// flops per byte, min(peak, intensity x bandwidth), and each counted row as a point.
std::string roofline_plot(const KernelsReport& k) {
  std::vector<Series> series;
  double lo = 0.01, hi = 1000.0;
  for (const auto& r : k.rows)
    if (r.counted && std::isfinite(r.intensity) && r.intensity > 0) {
      lo = std::min(lo, r.intensity / 2);
      hi = std::max(hi, r.intensity * 2);
    }
  for (int p = 0; p < 2; ++p) {
    const double peak = p == 0 ? k.fp32.gflops : k.fp64.gflops;
    if (peak <= 0 || k.bandwidth <= 0) continue;
    Series roof;
    roof.name = std::string(p == 0 ? "fp32" : "fp64") + " roof";
    roof.dashed = p == 1;
    const double ridge = peak / k.bandwidth;
    for (double x : {lo, std::clamp(ridge, lo, hi), hi}) {
      roof.x.push_back(x);
      roof.y.push_back(std::min(peak, x * k.bandwidth));
    }
    series.push_back(roof);
  }
  for (const char* prec : {"fp32", "fp64"}) {
    Series pts;
    pts.name = std::string("kernels ") + prec;
    pts.line = false;
    for (const auto& r : k.rows)
      if (r.counted && r.precision == prec && std::isfinite(r.intensity)) {
        pts.x.push_back(r.intensity);
        pts.y.push_back(r.gflops);
        pts.labels.push_back(r.kernel);
      }
    if (!pts.x.empty()) series.push_back(pts);
  }
  return svg_plot("roofline (" + k.shape + " shape)", "flops per byte (counted)", "GFLOP/s (counted flops / device s)",
                  series, true, true);
}

void kernels_section(std::ostringstream& o, const KernelsReport& k) {
  o << "<h2>Kernels against the device's measured peak</h2>\n";
  o << "<p>Kernel shape <b>" << esc(k.shape) << "</b>. Measured peaks on this device (kernels/device_peak.cl): fp32 <b>"
    << fmt(k.fp32.gflops, "%.1f") << " GFLOP/s</b>, fp64 <b>" << fmt(k.fp64.gflops, "%.1f")
    << " GFLOP/s</b> (8 independent FMA chains on 16-lane vectors a work-item), streaming triad <b>"
    << fmt(k.bandwidth, "%.1f") << " GB/s</b> (" << fmt(k.bandwidth_bytes / 1e6, "%.0f")
    << " MB a launch). Each hot kernel ran through the library's entries at the size in the table, a warm-up then "
       "the median of its runs; device seconds from OpenCL event profiling (the row's kernel only), wall seconds of "
       "the whole call beside them. Flops and bytes are <b>counted</b>, not estimated: "
    << esc(kernel_op_count_source())
    << ". A row is compute-bound where its flops per byte reach the ridge (peak / bandwidth), and its fraction is of "
       "the peak GFLOP/s of its precision; else of the triad's GB/s (above 100 %: the caches serve its loads). The "
       "flops peak's fraction is beside it whatever the side. Below "
    << fmt(100 * kKernelLowFraction, "%.0f") << "% the table says what bounds it.</p>\n";
  o << "<div class=\"plots\">" << roofline_plot(k) << "</div>\n";
  o << "<table><tr><th>kernel</th><th>launch</th><th>precision</th><th>throughput</th><th>device (ms)</th><th>wall "
       "(ms)</th><th>flops/unit</th><th>bytes/unit</th><th>GFLOP/s</th><th>GB/s</th><th>flops/byte</th><th>bound</th>"
       "<th>of the roof</th><th>of the flops peak</th><th>what bounds it</th></tr>\n";
  for (const auto& r : k.rows) {
    o << "<tr><td><code>" << esc(r.kernel) << "</code></td><td style=\"text-align:left\">" << esc(r.launch)
      << "</td><td>" << r.precision << "</td><td>" << fmt(r.units_per_second, "%.3g") << " " << esc(r.unit)
      << "s/s</td><td>" << fmt(r.device_seconds * 1e3, "%.2f") << "</td><td>" << fmt(r.wall_seconds * 1e3, "%.2f")
      << "</td>";
    if (r.counted)
      o << "<td>" << fmt(r.flops_per_unit, "%.4g") << "</td><td>" << fmt(r.bytes_per_unit, "%.3g") << "</td><td>"
        << fmt(r.gflops, "%.2f") << "</td><td>" << fmt(r.gbytes_per_second, "%.2f") << "</td><td>"
        << fmt(r.intensity, "%.3g") << "</td><td>" << r.bound << "</td><td><b>" << pct(r.fraction) << "</b></td><td>"
        << pct(r.flops_fraction) << "</td><td style=\"text-align:left\">" << esc(r.limit) << "</td></tr>\n";
    else
      o << "<td colspan=\"9\">"
        << (r.stale ? "counted on other sources of its kernel file: count again"
                    : "not counted in the " + esc(k.shape) + " shape")
        << " (scripts/count_kernel_ops.sh)</td></tr>\n";
  }
  o << "</table>\n";
  o << "<p class=\"note\">Flops per lane: add, subtract, multiply, divide 1; fma 2; sqrt, rsqrt and each "
       "transcendental 1 (their share of the flops is a cause the last column names: each takes many cycles). Bytes: "
       "every global and constant load and store the kernel executed, so re-reads a cache serves count too and the "
       "flops per byte are a lower bound. The prefilter rows were counted on a 64&sup2; chain (measured: 128&sup2;; "
       "the "
       "same levels' roughness and mix of sizes) and the conversion at 32&sup2; (measured: 256&sup2;, the same "
       "supersampling): the walk refines deeper on a finer source, so the walks' flops per texel, and GFLOP/s, are "
       "lower bounds.</p>\n";
}

}  // namespace

std::string report_html(const Report& r) {
  std::ostringstream o;
  o << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>brdfbake report: " << esc(r.device)
    << "</title>\n<style>" << kStyle << "</style></head><body>\n";
  // The page says what it answers: a bake sweep alone (report --kinds bake) is not the tables' report.
  const bool tables = !r.dfg.empty() || !r.fresnel.empty() || !r.prefilter.empty();
  o << "<h1>"
    << (tables               ? "brdfbake: accuracy against time"
        : !r.kernels.empty() ? "brdfbake: where each kernel stands against its device"
                             : "brdfbake: what each bake setting costs")
    << "</h1>\n";
  o << "<p class=\"meta\">" << esc(r.generator) << ", " << esc(r.date) << "<br>Device: <b>" << esc(r.device) << "</b> ("
    << esc(r.device_details) << ")<br>Machine: " << r.cores << " cores; load average (1, 5, 15 min) "
    << load_text(r.load_before) << " at the start, " << load_text(r.load_after)
    << " at the end: times stretch with the load, errors do not<br>"
    << "The report took " << fmt(r.seconds, "%.1f") << " s"
    << (r.options.command.empty() ? "" : ": <code>" + esc(r.options.command) + "</code>") << "</p>\n";
  if (!r.bake.empty())
    o << "<p class=\"note\">Which bake settings to use for each target engine: what each setting of <code>brdfbake "
         "bake</code> costs in wall time and bytes, and how far the target's split-sum render of material spheres lit "
         "by the bake's files then is from the converged reference render. The first table answers with a "
         "recommended setting per target; the plots and tables below it give every setting's numbers. The numbers "
         "are also in the JSON file beside this page.</p>\n";
  if (tables)
    o << "<p class=\"note\">Times are device seconds from OpenCL event profiling (the median of up to three runs "
         "after a warm-up; one run above 0.1 s), without program builds or transfers. DFG errors are the max (and "
         "RMS) over every channel and cell of |table &minus; reference| / max(1, |reference|) against the converged "
         "scalar double reference at the same cells. The numbers are also in the JSON file beside this page.</p>\n";
  for (const auto& k : r.kernels) kernels_section(o, k);
  for (const auto& b : r.bake) bake_section(o, b);  // first: "which settings, for how long, at what error"
  for (const auto& s : r.dfg) dfg_section(o, s);
  if (!r.fresnel.empty()) fresnel_section(o, r.fresnel);
  prefilter_section(o, r.prefilter);
  o << "</body></html>\n";
  return o.str();
}

}  // namespace brdfbake
