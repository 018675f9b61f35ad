// The environment's quadtree for the reference render (tree.hpp, kernels/preview.cl).
#include "families/preview/tree.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "brdfbake/error.hpp"

namespace brdfbake::detail::preview {

namespace {

// Spreads the low 16 bits of v to the even bits.
unsigned spread(unsigned v) {
  v &= 0xFFFFu;
  v = (v | (v << 8)) & 0x00FF00FFu;
  v = (v | (v << 4)) & 0x0F0F0F0Fu;
  v = (v | (v << 2)) & 0x33333333u;
  v = (v | (v << 1)) & 0x55555555u;
  return v;
}
unsigned compact(unsigned v) {
  v &= 0x55555555u;
  v = (v | (v >> 1)) & 0x33333333u;
  v = (v | (v >> 2)) & 0x0F0F0F0Fu;
  v = (v | (v >> 4)) & 0x00FF00FFu;
  v = (v | (v >> 8)) & 0x0000FFFFu;
  return v;
}

double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// The moments a cell sums (double while building).
struct Moments {
  double omega = 0.0;
  double g[3] = {0.0, 0.0, 0.0};                                         // int l dl
  double lo[3] = {0.0, 0.0, 0.0};                                        // int L dl
  double m[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};  // int l L_c dl
  void add(const Moments& o) {
    omega += o.omega;
    for (int k = 0; k < 3; ++k) {
      g[k] += o.g[k];
      lo[k] += o.lo[k];
      for (int c = 0; c < 3; ++c) m[c][k] += o.m[c][k];
    }
  }
};

Vec3 direction(double phi, double theta) {
  return {std::sin(phi) * std::cos(theta), std::sin(theta), std::cos(phi) * std::cos(theta)};
}

// The largest angle from the unit direction c to the cell of columns [c0, c1) and rows [r0, r1) of a
// width x height equirect: at a corner (the cosine to c falls monotonically along every meridian
// away from its nearest point, and along every parallel away from c's meridian, which bisects the
// cell by symmetry).
double cell_radius(const Vec3& c, int c0, int c1, int r0, int r1, int width, int height) {
  const double phi[2] = {2.0 * M_PI * (0.5 - double(c0) / width), 2.0 * M_PI * (0.5 - double(c1) / width)};
  const double theta[2] = {M_PI * (0.5 - double(r0) / height), M_PI * (0.5 - double(r1) / height)};
  double smallest = 1.0;
  for (double p : phi)
    for (double t : theta) smallest = std::min(smallest, math::dot(c, direction(p, t)));
  return std::acos(std::clamp(smallest, -1.0, 1.0));
}

}  // namespace

int tree_index(int top, int k, int x, int y) {
  const int side_bits = top - k;
  const int root = x >> side_bits;
  const unsigned mask = (1u << side_bits) - 1u;
  return (root << (2 * side_bits)) + int(spread(unsigned(x) & mask) | (spread(unsigned(y)) << 1));
}

void tree_cell_position(int top, int k, int index, int& x, int& y) {
  const int side_bits = top - k;
  const int root = index >> (2 * side_bits);
  const unsigned rem = unsigned(index) & ((1u << (2 * side_bits)) - 1u);
  x = (root << side_bits) | int(compact(rem));
  y = int(compact(rem >> 1));
}

double equirect_rect_solid_angle(double u0, double u1, double v0, double v1) {
  // Omega = dphi (sin tb - sin ta), with the difference as a product
  const double dphi = 2.0 * M_PI * (u1 - u0), dt = M_PI * (v1 - v0), tm = M_PI * (0.5 - 0.5 * (v0 + v1));
  return dphi * 2.0 * std::cos(tm) * std::sin(0.5 * dt);
}

Vec3 equirect_rect_moment(double u0, double u1, double v0, double v1) {
  const double dphi = 2.0 * M_PI * (u1 - u0), pm = 2.0 * M_PI * (0.5 - 0.5 * (u0 + u1));
  const double dt = M_PI * (v1 - v0), tm = M_PI * (0.5 - 0.5 * (v0 + v1));
  const double sh = std::sin(0.5 * dphi);
  const double ds = 2.0 * std::cos(tm) * std::sin(0.5 * dt), ss = 2.0 * std::sin(tm) * std::cos(0.5 * dt);
  const double q = 0.5 * (dt + std::cos(2.0 * tm) * std::sin(dt));  // int cos^2 theta dtheta
  return {2.0 * std::sin(pm) * sh * q, 0.5 * dphi * ds * ss, 2.0 * std::cos(pm) * sh * q};
}

EnvTree build_env_tree(const EnvImage& env, bool bright) {
  if (env.layout != EnvImage::Layout::Equirect || env.width != 2 * env.height || env.height < 1)
    throw Error("the reference render needs an equirect environment (width = 2 height)");
  EnvTree t;
  t.image_width = env.width;
  t.image_height = env.height;
  t.image = env.rgb;
  int p = 2;
  while (p < env.width) p *= 2;
  t.top = 0;
  while ((2 << t.top) < p) ++t.top;  // level 0: 2^(top + 1) x 2^top
  const int levels = t.top + 1;
  t.start = std::max(0, t.top - 5);

  // The bright pixels: above 16 x the mean luminance, at most the 256 brightest.
  std::vector<uint8_t> is_bright(size_t(env.width) * size_t(env.height), 0);
  if (bright) {
    double sum = 0.0, omega = 0.0;
    for (int y = 0; y < env.height; ++y) {
      const double w =
          equirect_rect_solid_angle(0.0, 1.0 / env.width, double(y) / env.height, double(y + 1) / env.height);
      for (int x = 0; x < env.width; ++x) {
        const float* l = &env.rgb[3 * (size_t(y) * size_t(env.width) + size_t(x))];
        sum += w * luminance(l[0], l[1], l[2]);
        omega += w;
      }
    }
    const double threshold = kBrightRatio * sum / omega;
    std::vector<std::pair<double, size_t>> candidates;
    for (size_t i = 0; i < is_bright.size(); ++i) {
      const float* l = &env.rgb[3 * i];
      const double lum = luminance(l[0], l[1], l[2]);
      if (lum > threshold) candidates.push_back({lum, i});
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    if (candidates.size() > size_t(kDefaultBrightTexels)) candidates.resize(size_t(kDefaultBrightTexels));
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    for (const auto& c : candidates) {
      is_bright[c.second] = 1;
      const int x = int(c.second % size_t(env.width)), y = int(c.second / size_t(env.width));
      t.bright_index.push_back(tree_index(t.top, 0, x, y));
      for (int k = 0; k < 3; ++k) t.bright_rgb.push_back(env.rgb[3 * c.second + size_t(k)]);
    }
  }

  // Level 0: the pixels' exact moments, separable in longitude and latitude.
  const int w0 = 2 << t.top, h0 = 1 << t.top;
  std::vector<std::vector<Moments>> m(static_cast<size_t>(levels));
  m[0].resize(size_t(w0) * size_t(h0));
  for (int y = 0; y < env.height; ++y) {
    const double v0 = double(y) / env.height, v1 = double(y + 1) / env.height;
    for (int x = 0; x < env.width; ++x) {
      const double u0 = double(x) / env.width, u1 = double(x + 1) / env.width;
      Moments& c = m[0][size_t(tree_index(t.top, 0, x, y))];
      c.omega = equirect_rect_solid_angle(u0, u1, v0, v1);
      const Vec3 g = equirect_rect_moment(u0, u1, v0, v1);
      static const float kBlack[3] = {0.0f, 0.0f, 0.0f};
      const size_t at = size_t(y) * size_t(env.width) + size_t(x);
      const float* l = is_bright[at] ? kBlack : &env.rgb[3 * at];
      const double gv[3] = {g.x, g.y, g.z};
      for (int k = 0; k < 3; ++k) {
        c.g[k] = gv[k];
        c.lo[k] = double(l[k]) * c.omega;
        for (int ch = 0; ch < 3; ++ch) c.m[ch][k] = gv[k] * double(l[ch]);
      }
      t.solid_angle += c.omega;
    }
  }
  for (int k = 1; k < levels; ++k) {
    const size_t n = size_t(w0 >> k) * size_t(h0 >> k);
    m[size_t(k)].resize(n);
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < 4; ++c) m[size_t(k)][i].add(m[size_t(k - 1)][4 * i + c]);
  }

  // The stored cells.
  size_t first = 0;
  for (int k = 0; k < levels; ++k) {
    const int gw = w0 >> k, gh = h0 >> k;
    t.levels.push_back({int(first), gw * gh, gw, gh});
    first += size_t(gw) * size_t(gh);
  }
  t.data.assign(first * size_t(kTreeFloats), 0.0f);
  for (int k = 0; k < levels; ++k) {
    const auto& lv = t.levels[size_t(k)];
    const int span = 1 << k;  // pixels a side
    for (int i = 0; i < lv[1]; ++i) {
      const Moments& c = m[size_t(k)][size_t(i)];
      if (!(c.omega > 0.0)) continue;
      float* out = &t.data[(size_t(lv[0]) + size_t(i)) * size_t(kTreeFloats)];
      int x = 0, y = 0;
      tree_cell_position(t.top, k, i, x, y);
      const double gl = std::sqrt(c.g[0] * c.g[0] + c.g[1] * c.g[1] + c.g[2] * c.g[2]);
      const Vec3 gn = gl > 0.0 ? Vec3{c.g[0] / gl, c.g[1] / gl, c.g[2] / gl} : Vec3{0.0, 1.0, 0.0};
      const int c0 = x * span, c1 = std::min((x + 1) * span, env.width);
      const int r0 = y * span, r1 = std::min((y + 1) * span, env.height);
      out[0] = float(gn.x);
      out[1] = float(gn.y);
      out[2] = float(gn.z);
      out[3] = float(gl / c.omega);
      out[4] = float(c.omega);
      out[5] = float(cell_radius(gn, c0, c1, r0, r1, env.width, env.height));
      for (int a = 0; a < 3; ++a) out[6 + a] = float(c.lo[a]);
      out[9] = float(luminance(c.lo[0], c.lo[1], c.lo[2]));
      for (int ch = 0; ch < 3; ++ch)
        for (int a = 0; a < 3; ++a) out[10 + 3 * ch + a] = float(c.m[ch][a]);
    }
  }
  return t;
}

}  // namespace brdfbake::detail::preview
