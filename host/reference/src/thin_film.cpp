// Thin-film interference Fresnel, scalar double (see the header for the formulation).
//
// Derivation, following Belcour & Barla 2017 sec. 3-4 and the KHR_materials_iridescence
// implementation section. Light from the outside (index n1) meets the film (n2, thickness d) on a
// base (n3). With R12, R23 the interface reflectances, T121 = 1 - R12 the round trip through the
// top interface, and r123 = sqrt(R12 R23), the Airy sum of the reflected amplitudes, squared and
// integrated over wavelength against a sensor S, is
//     I = C0 + sum_{m >= 1} Cm * 2 S_m,     C0 = R12 + Rs,   Rs = T121^2 R23 / (1 - R12 R23),
//     Cm = (Rs - T121) r123^m,              S_m = Re ∫ S(λ) exp(i m (2π OPD / λ + phi)) dλ,
// with OPD = 2 n2 d cos(theta2) the optical path difference (Snell: n1 sin θ1 = n2 sin θ2) and phi
// the sum of the phase shifts of the reflections inside the film: pi at an interface towards a
// denser medium. With S the CIE XYZ matching functions fitted by Gaussians in frequency, S_m is the
// Gaussian's Fourier transform: val sqrt(2π var) cos(pos φ + shift) exp(-var φ²), φ = 2π OPD 1e-9
// (Belcour & Barla's supplemental). The series stops at m = 2: r123^3 is below 1e-3 for any
// dielectric, and exp(-var φ²) kills higher orders of all but the thinnest films.
#include "brdfbake/reference/thin_film.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::reference {

namespace {

using brdfbake::math::kPi;

// Schlick 1994 with F90 = 1, as the specification evaluates each interface.
double schlick(double f0, double cos_theta) {
  const double m = 1.0 - cos_theta;
  const double m2 = m * m;
  return f0 + (1.0 - f0) * m2 * m2 * m;
}

// The Hermite smoothstep of GLSL.
double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

double channel(const Rgb& c, int i) { return i == 0 ? c.r : i == 1 ? c.g : c.b; }
void set_channel(Rgb& c, int i, double v) { (i == 0 ? c.r : i == 1 ? c.g : c.b) = v; }

struct Interfaces {
  bool total_internal_reflection = false;
  double film_ior = 1.0, cos2 = 1.0;
  double r12 = 0.0, t121 = 1.0, phi21 = 0.0;
  Rgb r23{0, 0, 0}, phi23{0, 0, 0};
};

Interfaces interfaces(double cos_theta, double thickness_nm, const ThinFilm& f) {
  Interfaces s;
  const double cos1 = std::clamp(cos_theta, 0.0, 1.0);
  // The film fades into the outside medium as its thickness goes to 0 (the specification's
  // smoothstep over the first 0.03 nm), so that a zero thickness has no interference.
  s.film_ior = f.outside_ior + (f.film_ior - f.outside_ior) * smoothstep(0.0, 0.03, thickness_nm);
  const double ratio = f.outside_ior / s.film_ior;
  const double sin2_sq = ratio * ratio * (1.0 - cos1 * cos1);
  const double cos2_sq = 1.0 - sin2_sq;
  if (cos2_sq < 0.0) {
    s.total_internal_reflection = true;
    return s;
  }
  s.cos2 = std::sqrt(cos2_sq);
  s.r12 = schlick(thin_film_ior_to_f0(s.film_ior, f.outside_ior), cos1);
  s.t121 = 1.0 - s.r12;
  const double phi12 = s.film_ior < f.outside_ior ? kPi : 0.0;
  s.phi21 = kPi - phi12;
  for (int c = 0; c < 3; ++c) {
    const double base_ior = thin_film_f0_to_ior(channel(f.base_f0, c));
    set_channel(s.r23, c, schlick(thin_film_ior_to_f0(base_ior, s.film_ior), s.cos2));
    set_channel(s.phi23, c, base_ior < s.film_ior ? kPi : 0.0);
  }
  return s;
}

}  // namespace

double thin_film_ior_to_f0(double n_t, double n_i) {
  const double r = (n_t - n_i) / (n_t + n_i);
  return r * r;
}

double thin_film_f0_to_ior(double f0) {
  const double s = std::sqrt(std::clamp(f0, 0.0, 0.9999));
  return (1.0 + s) / (1.0 - s);
}

Rgb thin_film_sensitivity(double opd_nm, const Rgb& shift) {
  const double phase = 2.0 * kPi * opd_nm * 1.0e-9;
  // Gaussian fits of x-bar (two lobes), y-bar and z-bar in frequency: amplitude, centre, variance.
  const double val[3] = {5.4856e-13, 4.4201e-13, 5.2481e-13};
  const double pos[3] = {1.6810e+06, 1.7953e+06, 2.2084e+06};
  const double var[3] = {4.3278e+09, 9.3046e+09, 6.6121e+09};
  double xyz[3];
  for (int k = 0; k < 3; ++k)
    xyz[k] = val[k] * std::sqrt(2.0 * kPi * var[k]) * std::cos(pos[k] * phase + channel(shift, k)) *
             std::exp(-phase * phase * var[k]);
  xyz[0] += 9.7470e-14 * std::sqrt(2.0 * kPi * 4.5282e+09) * std::cos(2.2399e+06 * phase + shift.r) *
            std::exp(-4.5282e+09 * phase * phase);
  for (double& v : xyz) v /= 1.0685e-7;  // the integral of y-bar: Y(0, 0) = 1
  // CIE XYZ -> linear Rec. 709 (sRGB primaries, D65).
  return Rgb{3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2],
             -0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2],
             0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2]};
}

Rgb thin_film_incoherent(double cos_theta, double thickness_nm, const ThinFilm& f) {
  const Interfaces s = interfaces(cos_theta, thickness_nm, f);
  if (s.total_internal_reflection) return Rgb{1.0, 1.0, 1.0};
  Rgb out{0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    const double r23 = channel(s.r23, c);
    const double r123 = std::clamp(s.r12 * r23, 1e-5, 0.9999);
    set_channel(out, c, s.r12 + s.t121 * s.t121 * r23 / (1.0 - r123));
  }
  return out;
}

Rgb thin_film_fresnel(double cos_theta, double thickness_nm, const ThinFilm& f) {
  const Interfaces s = interfaces(cos_theta, thickness_nm, f);
  if (s.total_internal_reflection) return Rgb{1.0, 1.0, 1.0};
  const double opd = 2.0 * s.film_ior * thickness_nm * s.cos2;
  Rgb phi{}, rs{}, cm{}, amplitude{}, out{};
  for (int c = 0; c < 3; ++c) {
    const double r23 = channel(s.r23, c);
    // R12 R23 clamped as the specification does: away from 0 (its square root multiplies) and 1.
    const double r123 = std::clamp(s.r12 * r23, 1e-5, 0.9999);
    set_channel(phi, c, s.phi21 + channel(s.phi23, c));
    set_channel(rs, c, s.t121 * s.t121 * r23 / (1.0 - r123));
    set_channel(cm, c, channel(rs, c) - s.t121);
    set_channel(amplitude, c, std::sqrt(r123));
    set_channel(out, c, s.r12 + channel(rs, c));  // C0
  }
  for (int m = 1; m <= 2; ++m) {
    const Rgb sm = thin_film_sensitivity(m * opd, Rgb{m * phi.r, m * phi.g, m * phi.b});
    for (int c = 0; c < 3; ++c) {
      set_channel(cm, c, channel(cm, c) * channel(amplitude, c));
      set_channel(out, c, channel(out, c) + channel(cm, c) * 2.0 * channel(sm, c));
    }
  }
  return Rgb{std::max(out.r, 0.0), std::max(out.g, 0.0), std::max(out.b, 0.0)};
}

}  // namespace brdfbake::reference
