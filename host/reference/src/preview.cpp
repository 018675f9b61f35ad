// The reference render's integrals by brute force (brdfbake/reference/preview.hpp).
#include "brdfbake/reference/preview.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/reference/charlie.hpp"
#include "brdfbake/reference/ggx.hpp"

namespace brdfbake::reference {

namespace {

// docs/CONVENTIONS.md: longitude phi = 2 pi (0.5 - u), latitude theta = pi (0.5 - v).
Vec3 equirect_dir(double u, double v) {
  const double phi = 2.0 * M_PI * (0.5 - u), theta = M_PI * (0.5 - v);
  return {std::sin(phi) * std::cos(theta), std::sin(theta), std::cos(phi) * std::cos(theta)};
}

double dot3(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// The integrand's two lobes at unit l: D V (n.l)+ and the same times (1 - v.h)^5; the sheen lobe:
// D_Charlie V_CharlieEstevezKulla (n.l)+ and 0.
void lobes(const Vec3& n, const Vec3& v, double n_dot_v, double alpha, bool sheen, const Vec3& l, double* g,
           double* gf) {
  *g = *gf = 0.0;
  const double nl = dot3(n, l);
  if (!(nl > 0.0)) return;
  Vec3 h{v.x + l.x, v.y + l.y, v.z + l.z};
  const double len = std::sqrt(dot3(h, h));
  if (!(len > 0.0)) return;
  h = {h.x / len, h.y / len, h.z / len};
  if (sheen) {
    *g = D_Charlie(dot3(n, h), alpha) * V_CharlieEstevezKulla(n_dot_v, nl, alpha) * nl;
    return;
  }
  const double value = D_GGX(dot3(n, h), alpha) * V_SmithGGXCorrelated(n_dot_v, nl, alpha) * nl;
  *g = value;
  *gf = value * std::pow(std::max(0.0, 1.0 - dot3(v, h)), 5.0);
}

}  // namespace

PreviewIntegrals preview_integrals(const float* rgb, int width, int height, const Vec3& n_in, const Vec3& v_in,
                                   double alpha, double subdivision, bool sheen, const PreviewFilm* film) {
  PreviewIntegrals out;
  // Unit vectors to the last bit: a narrow lobe's D near its peak is 1 - (n.h)^2 over alpha^2, and a
  // normal of length 1 + 6e-8 (a float normal) moves that by 2% at alpha = 0.0025.
  const double ln = std::sqrt(dot3(n_in, n_in)), lv = std::sqrt(dot3(v_in, v_in));
  const Vec3 n{n_in.x / ln, n_in.y / ln, n_in.z / ln}, v{v_in.x / lv, v_in.y / lv, v_in.z / lv};
  const double n_dot_v = std::max(dot3(n, v), 1e-7);
  const Vec3 r{2.0 * n_dot_v * n.x - v.x, 2.0 * n_dot_v * n.y - v.y, 2.0 * n_dot_v * n.z - v.z};
  const double du = 1.0 / width, dv = 1.0 / height;
  for (int y = 0; y < height; ++y) {
    // the pixel's angular extent: its latitude span and its widest longitude span
    const double t0 = M_PI * (0.5 - y * dv), t1 = M_PI * (0.5 - (y + 1) * dv);
    const double wide = std::max(std::cos(t0), std::cos(t1));
    const double size = std::hypot(M_PI * dv, 2.0 * M_PI * du * wide);
    for (int x = 0; x < width; ++x) {
      const float* l = rgb + 3 * (size_t(y) * size_t(width) + size_t(x));
      const Vec3 c = equirect_dir((x + 0.5) * du, (y + 0.5) * dv);
      int q = 1;
      const double nc = dot3(n, c);
      if (std::fabs(nc) < size) q = std::max(q, int(subdivision));  // across the horizon
      if (nc < -size) continue;                                     // wholly below it
      if (alpha > 0.0 && !sheen) {
        const double d = std::acos(std::clamp(dot3(c, r), -1.0, 1.0));
        // the lobe is 2 alpha wide in the plane of incidence and 2 alpha n.v across it (dl = 4 (v.h) dh)
        const double scale = std::max(2.0 * alpha * n_dot_v, d - size);
        q = std::max(q, int(std::ceil(subdivision * size / scale)));
      }
      q = std::min(q, 1024);
      for (int b = 0; b < q; ++b) {
        const double va = (y + double(b) / q) * dv, vb = (y + double(b + 1) / q) * dv;
        // the exact solid angle of the sub-row's cells: dphi (sin theta_a - sin theta_b)
        const double omega = (2.0 * M_PI * du / q) * (std::sin(M_PI * (0.5 - va)) - std::sin(M_PI * (0.5 - vb)));
        for (int a = 0; a < q; ++a) {
          const Vec3 s = equirect_dir((x + (a + 0.5) / q) * du, 0.5 * (va + vb));
          const double ns = dot3(n, s);
          if (!(ns > 0.0)) continue;
          for (int k = 0; k < 3; ++k) out.irr[size_t(k)] += ns * double(l[k]) * omega;
          if (!(alpha > 0.0)) continue;
          double g = 0.0, gf = 0.0;
          lobes(n, v, n_dot_v, alpha, sheen, s, &g, &gf);
          if (film) {
            if (!(g > 0.0)) continue;
            // the thin film's Fresnel at v.h = |v + l| / 2, per channel
            const Vec3 h{v.x + s.x, v.y + s.y, v.z + s.z};
            const Rgb f = thin_film_fresnel(0.5 * std::sqrt(dot3(h, h)), film->thickness_nm, film->film);
            const double fc[3] = {f.r, f.g, f.b};
            for (int k = 0; k < 3; ++k) out.s1[size_t(k)] += g * fc[k] * double(l[k]) * omega;
            continue;
          }
          for (int k = 0; k < 3; ++k) {
            out.s1[size_t(k)] += g * double(l[k]) * omega;
            out.s2[size_t(k)] += gf * double(l[k]) * omega;
          }
        }
      }
    }
  }
  if (!(alpha > 0.0)) {
    // the mirror: the pixel r falls in
    const double u = 0.5 - std::atan2(r.x, r.z) / (2.0 * M_PI);
    const double vv = 0.5 - std::asin(std::clamp(r.y, -1.0, 1.0)) / M_PI;
    const int x = std::clamp(int(std::floor(u * width)), 0, width - 1);
    const int y = std::clamp(int(std::floor(vv * height)), 0, height - 1);
    const float* l = rgb + 3 * (size_t(y) * size_t(width) + size_t(x));
    const double fc = std::pow(1.0 - n_dot_v, 5.0);
    for (int k = 0; k < 3; ++k) {
      out.s1[size_t(k)] = l[k];
      out.s2[size_t(k)] = fc * double(l[k]);
    }
    if (film) {
      const Rgb f = thin_film_fresnel(n_dot_v, film->thickness_nm, film->film);
      const double fr[3] = {f.r, f.g, f.b};
      for (int k = 0; k < 3; ++k) {
        out.s1[size_t(k)] *= fr[k];
        out.s2[size_t(k)] = 0.0;
      }
    }
  }
  return out;
}

double preview_integrals_work(int width, int height, double alpha, double subdivision, bool sheen) {
  // every pixel once, the horizon's (about 2 width of them) subdivided, and the lobe's core: the
  // pixels within a few lobe widths of r, each split to the lobe's width / subdivision
  const double pixel = M_PI / height;
  const double horizon = 2.0 * width * subdivision * subdivision;
  double lobe = 0.0;
  if (alpha > 0.0 && !sheen) {
    // the lobe's core at n.v ~ 0.25 (the work grows like 1 / n.v towards the rims)
    const double q = std::min(1024.0, std::ceil(subdivision * pixel / (0.5 * alpha)));
    const double core = std::pow(std::max(1.0, 4.0 * alpha / pixel), 2.0);
    lobe = core * q * q;
  }
  return double(width) * height + horizon + lobe;
}

}  // namespace brdfbake::reference
