// Split-sum DFG lookup tables over (n_dot_v, perceptual roughness).
//
// Compile-time choices (host/src/families/dfg_lut/opencl.cpp defines exactly one of each group):
//   table:     BRDFBAKE_LUT_GGX            -> scale, bias, burley_albedo
//              BRDFBAKE_LUT_GGX_MULTISCATTER -> bias (sum Fc V), albedo (sum V), burley_albedo
//              BRDFBAKE_LUT_CHARLIE        -> sheen albedo
//   estimator: BRDFBAKE_EST_QUADRATURE | BRDFBAKE_EST_VNDF | BRDFBAKE_EST_NDF | BRDFBAKE_EST_UNIFORM
//   sheen:     BRDFBAKE_SHEEN_NEUBELT (else Estevez & Kulla's fitted Lambda)
//   shape:     BRDFBAKE_DFG_GROUPS (the GPU shape, docs/DEVICES.md): a work-group a cell, its
//              work-items taking every get_local_size(0)-th chunk of polar nodes (or samples), their
//              sums added in local memory; else (the CPU shape) a work-item a cell
//
// Frame: n = +z, v = (sin_v, 0, n_dot_v). A microfacet normal h at polar angle theta_h and azimuth
// phi reflects v into l = 2 (v.h) h - v, with n.l = 2 (v.h)(n.h) - n.v.
#include "common/real.clh"
#include "common/fresnel.clh"
#include "common/ggx.clh"
#include "common/charlie.clh"
#include "common/diffuse.clh"
#include "common/sampling.clh"

#if BRDFBAKE_LANES != 8
#error "the host pads the quadrature nodes to multiples of 8 lanes"
#endif

// The polar nodes (and samples) a work-item takes: all of them in the CPU shape; in the GPU shape
// every get_local_size(0)-th chunk of BRDFBAKE_LANES, from its local id.
#ifdef BRDFBAKE_DFG_GROUPS
#define DFG_FIRST ((int)get_local_id(0))
#define DFG_STRIDE ((int)get_local_size(0))
#else
#define DFG_FIRST 0
#define DFG_STRIDE 1
#endif
#define DFG_NODES(k, n_xi) for (int k = DFG_FIRST * BRDFBAKE_LANES; k < (n_xi); k += DFG_STRIDE * BRDFBAKE_LANES)

// ---------------------------------------------------------------------------------------------
// Integrands in half-vector space.
//
// The albedo integral of a lobe f = D V F over l, with dl = 4 (v.h) dh (the reflection Jacobian),
// is I = int D(h) V n.l 4 (v.h) dh. Writing the measure D(h) (n.h) dh = dxi dphi / (2 pi), where
// xi is the CDF of the lobe's polar angle (D is normalised so that int D (n.h) dh = 1), gives
//   I = (1 / 2 pi) int_0^1 dxi int_0^2pi dphi  V n.l 4 (v.h) / (n.h).
// For GGX with V = G2 / (4 n.l n.v) the integrand is w = G2 (v.h) / ((n.v)(n.h)): the classic
// importance-sampling weight. Points where n.l <= 0 contribute 0 (v.h > 0 follows from n.l > 0).
// ---------------------------------------------------------------------------------------------

// n.l and v.h for the normal (sin_h cos_phi, sin_h sin_phi, cos_h).
inline real2 reflect_cosines(real n_dot_v, real sin_v, real sin_h, real cos_h, real cos_phi) {
  const real v_dot_h = sin_v * sin_h * cos_phi + n_dot_v * cos_h;
  return (real2)(R(2.0) * v_dot_h * cos_h - n_dot_v, v_dot_h);
}

// GGX: (1 - Fc) w and Fc w, the integrands of scale and bias.
inline real2 ggx_weight(real n_dot_v, real sin_v, real sin_h, real cos_h, real cos_phi, real alpha) {
  const real2 c = reflect_cosines(n_dot_v, sin_v, sin_h, cos_h, cos_phi);
  if (c.x <= R(0.0)) return (real2)(R(0.0), R(0.0));
  const real w = G2_SmithGGXCorrelated(n_dot_v, c.x, alpha) * c.y / (n_dot_v * cos_h);
  const real fc = schlick_weight(c.y);
  return (real2)((R(1.0) - fc) * w, fc * w);
}

// Charlie: V n.l 4 (v.h) / (n.h).
inline real charlie_weight(real n_dot_v, real sin_v, real sin_h, real cos_h, real cos_phi, real alpha) {
  const real2 c = reflect_cosines(n_dot_v, sin_v, sin_h, cos_h, cos_phi);
  if (c.x <= R(0.0) || cos_h <= R(0.0)) return R(0.0);
#ifdef BRDFBAKE_SHEEN_NEUBELT
  const real vnl = V_Neubelt_times_nl(n_dot_v, c.x);
#else
  const real vnl = V_CharlieEstevezKulla_times_nl(n_dot_v, c.x, alpha);
#endif
  return vnl * R(4.0) * c.y / cos_h;
}

// ---------------------------------------------------------------------------------------------
// Deterministic quadrature (BRDFBAKE_EST_QUADRATURE).
//
// 1. The horizon. n.l = 0 cuts the (theta_h, phi) domain along a curve, and any product rule laid
// across that kink converges slowly. The curve has a closed form:
//   n.l > 0  <=>  2 cos_h (sin_v sin_h cos_phi + n.v cos_h) > n.v
//            <=>  cos_phi > c(theta_h) = -cot(theta_v) cot(2 theta_h),
// so every phi is valid for theta_h <= theta_1 = pi/4 - theta_v/2 (c <= -1), none for
// theta_h >= theta_2 = pi/4 + theta_v/2 (c >= 1), and phi in [0, acos c] in between. With
// tau = tan(theta_v / 2) = sin_v / (1 + n.v): tan(theta_1) = (1 - tau)/(1 + tau) = 1/tan(theta_2).
// Panel A (theta_h < theta_1) takes the midpoint rule in phi over the whole circle (spectrally
// accurate for a smooth periodic integrand; the mirror symmetry phi -> -phi halves it); panel B
// (theta_1 < theta_h < theta_2) takes Gauss-Legendre in phi over [0, acos c], where the integrand
// goes to zero smoothly at the horizon.
//
// 2. The polar variable. Uniform lobe mass (xi) resolves the lobe's peak, but at grazing view the
// integrand w grows like 1/(n.v)^2 where h nears v, a sliver of xi of relative size (alpha n.v)^2.
// A logarithmic variable resolves every scale at once: GGX uses y = log(eta), eta = 1 - xi, on both
// panels (d xi = eta dy); Charlie uses y = log(cos theta_h) on panel B, with its density
// d xi / dy = (2 + 1/alpha) sin^(1/alpha) cos^2, and xi itself on panel A. Panel B's nodes also go
// through u = (1 - cos(pi x)) / 2, whose vanishing slope at both ends absorbs the square-root
// behaviour of acos(c) at theta_1 and theta_2. The convergence this buys is in docs/BENCHMARKS.md.
//
// Node buffer q (built on the host, in `real`): n_xi Gauss-Legendre nodes then weights on [0,1];
// n_xi panel-B nodes u(x) then weights (pi/2) sin(pi x) w; n_phi Gauss-Legendre nodes then weights
// on [0,1]; n_phi midpoint cosines cos((m + 0.5) pi / n_phi); 8 Gauss-Legendre nodes then weights
// for the diffuse integral. n_xi is a multiple of BRDFBAKE_LANES.
// ---------------------------------------------------------------------------------------------
#define Q_PHI_OFFSET (4 * n_xi)
#define Q_PHI_W_OFFSET (4 * n_xi + n_phi)
#define Q_MID_OFFSET (4 * n_xi + 2 * n_phi)
#define Q_D_X(k) q[4 * n_xi + 3 * n_phi + (k)]
#define Q_D_W(k) q[4 * n_xi + 3 * n_phi + 8 + (k)]

// The inner loops run BRDFBAKE_LANES polar nodes at once (one per lane), so the per-node set-up
// (exp, square roots, acos) is vectorised too; n_xi is padded to a multiple of the width with
// zero-weight nodes.
#if defined(BRDFBAKE_LUT_CHARLIE)
// Widest panel of Charlie's panel B in y = log(cos theta_h): log(1024), so one panel covers every
// n.v >= 1/512 (the range is about log(2 / n.v)).
#define CHARLIE_PANEL_WIDTH R(6.93)
typedef realv acc_t;
// Charlie's integrand V n.l 4 (v.h) / (n.h), times the node weights pw.
inline acc_t lobe_lanes(real n_dot_v, real sin_v, realv sin_h, realv cos_h, realv cos_phi, realv pw,
                        real alpha) {
  const realv v_dot_h = sin_v * sin_h * cos_phi + n_dot_v * cos_h;
  const realv n_dot_l = R(2.0) * v_dot_h * cos_h - n_dot_v;
  const realv nl = fmax(n_dot_l, (realv)R(1e-30));
#ifdef BRDFBAKE_SHEEN_NEUBELT
  const realv vnl = V_Neubelt_times_nl_v(n_dot_v, nl);
#else
  const realv vnl = V_CharlieEstevezKulla_times_nl_v(n_dot_v, nl, alpha);
#endif
  return n_dot_l > R(0.0) ? pw * vnl * R(4.0) * v_dot_h / cos_h : (realv)R(0.0);
}
inline real2 acc_total(acc_t a) { return (real2)(lanes_sum(a), R(0.0)); }
#else
typedef struct {
  realv scale, bias;
} acc_t;
// GGX's (1 - Fc) w and Fc w, w = G2 (v.h) / ((n.v)(n.h)), times the node weights pw (G2 in its
// one-division lane form, G2_SmithGGXCorrelated_v).
inline acc_t lobe_lanes(real n_dot_v, real sin_v, realv sin_h, realv cos_h, realv cos_phi, realv pw,
                        real alpha) {
  const realv v_dot_h = sin_v * sin_h * cos_phi + n_dot_v * cos_h;
  const realv n_dot_l = R(2.0) * v_dot_h * cos_h - n_dot_v;
  const realv nl = fmax(n_dot_l, (realv)R(0.0));
  const realv g2 = G2_SmithGGXCorrelated_v(n_dot_v, nl, alpha);
  const realv w = pw * g2 * v_dot_h / (n_dot_v * cos_h);
  const realv fc = schlick_weight_v(v_dot_h);
  acc_t r;
  r.scale = w - fc * w;
  r.bias = fc * w;
  return r;
}
inline void acc_add(acc_t* a, acc_t b) {
  a->scale += b.scale;
  a->bias += b.bias;
}
inline real2 acc_total(acc_t a) { return (real2)(lanes_sum(a.scale), lanes_sum(a.bias)); }

#endif

#if defined(BRDFBAKE_LUT_CHARLIE)
#define ACC_ADD(a, b) ((a) += (b))
#define ACC_ZERO ((realv)R(0.0))
#else
#define ACC_ADD(a, b) acc_add(&(a), (b))
#define ACC_ZERO ((acc_t){(realv)R(0.0), (realv)R(0.0)})
#endif

// cos(t) for t in [0, pi] as -sin(t - pi/2) by its Taylor polynomial, odd terms to s^11 in fp32
// (truncation below 6e-8) and to s^19 in fp64 (below 3e-16): the library cos costs several times
// more and panel B evaluates one per node.
inline realv cos_0_pi(realv t) {
  const realv s = t - R(1.57079632679489661923);
  const realv s2 = s * s;
#ifdef BRDFBAKE_FP64
  realv p = (realv)(R(-1.0) / R(121645100408832000.0));  // -1/19!
  p = p * s2 + R(1.0) / R(355687428096000.0);             // 1/17!
  p = p * s2 - R(1.0) / R(1307674368000.0);               // 1/15!
  p = p * s2 + R(1.0) / R(6227020800.0);                  // 1/13!
  p = p * s2 - R(1.0) / R(39916800.0);                    // 1/11!
#else
  realv p = (realv)(R(-1.0) / R(39916800.0));  // -1/11!
#endif
  p = p * s2 + R(1.0) / R(362880.0);
  p = p * s2 - R(1.0) / R(5040.0);
  p = p * s2 + R(1.0) / R(120.0);
  p = p * s2 - R(1.0) / R(6.0);
  p = p * s2 + R(1.0);
  return -(p * s);
}

// phi_max of panel B: acos(-cot(theta_v) cot(2 theta_h)), cot(2x) = (cos^2 - sin^2) / (2 sin cos).
inline realv horizon_phi(real n_dot_v, real sin_v, realv sin_h, realv cos_h) {
  const realv c = -(n_dot_v / sin_v) * (cos_h - sin_h) * (cos_h + sin_h) / (R(2.0) * sin_h * cos_h);
  return acos(clamp(c, R(-1.0), R(1.0)));
}

// tan(theta_1) for the horizon split; tan(theta_2) = 1 / tan(theta_1).
inline real tan_theta1(real n_dot_v, real sin_v) {
  const real tau = sin_v / (R(1.0) + n_dot_v);
  return (R(1.0) - tau) / (R(1.0) + tau);
}

// Panel A over BRDFBAKE_LANES polar nodes: the midpoint rule over the half circle.
inline acc_t panel_full(real n_dot_v, real sin_v, realv sin_h, realv cos_h, realv w, real alpha,
                        constant real* q, int n_xi, int n_phi) {
  acc_t acc = ACC_ZERO;
  const realv wm = w * (BRDFBAKE_PI / (real)n_phi);
  for (int m = 0; m < n_phi; ++m)
    ACC_ADD(acc, lobe_lanes(n_dot_v, sin_v, sin_h, cos_h, (realv)q[Q_MID_OFFSET + m], wm, alpha));
  return acc;
}

// Panel B over BRDFBAKE_LANES polar nodes: Gauss-Legendre over [0, phi_max].
inline acc_t panel_cut(real n_dot_v, real sin_v, realv sin_h, realv cos_h, realv w, real alpha,
                       constant real* q, int n_xi, int n_phi) {
  const realv phi_max = horizon_phi(n_dot_v, sin_v, sin_h, cos_h);
  const realv wp = w * phi_max;
  acc_t acc = ACC_ZERO;
  for (int m = 0; m < n_phi; ++m)
    ACC_ADD(acc, lobe_lanes(n_dot_v, sin_v, sin_h, cos_h, cos_0_pi(phi_max * q[Q_PHI_OFFSET + m]),
                            wp * q[Q_PHI_W_OFFSET + m], alpha));
  return acc;
}

inline real2 lobe_quadrature(real n_dot_v, real sin_v, real alpha, constant real* q, int n_xi,
                             int n_phi) {
  const real t1 = tan_theta1(n_dot_v, sin_v);
  acc_t acc = ACC_ZERO;
#if defined(BRDFBAKE_LUT_CHARLIE)
  const real e = R(2.0) + R(1.0) / alpha;
  const real sin1 = t1 / sqrt(R(1.0) + t1 * t1), cos1 = R(1.0) / sqrt(R(1.0) + t1 * t1);
  // Panel A: xi = sin^(2 + 1/alpha) in [0, xi_1]. Powers go through logarithms, and cos through
  // expm1: sin^(1/alpha) with 1/alpha up to 1e7 would amplify a rounding of sin a million-fold.
  const real log_xi1 = e * log(sin1);
  if (log_xi1 > R(-700.0)) {
    DFG_NODES(k, n_xi) {
      const realv log_s = (log_xi1 + log(vload_lanes(0, q + k))) * (alpha / (R(2.0) * alpha + R(1.0)));
      const realv s = exp(log_s);
      const realv c = sqrt(-expm1(R(2.0) * log_s));
      ACC_ADD(acc, panel_full(n_dot_v, sin_v, s, c, exp(log_xi1) * vload_lanes(0, q + n_xi + k), alpha, q,
                              n_xi, n_phi));
    }
  }
  // Panel B: y = log(cos theta_h) from log(cos theta_2) = log(sin theta_1) up to log(cos theta_1),
  // with density d xi / dy = (2 + 1/alpha) sin^(1/alpha) cos^2, sin^(1/alpha) = exp(log1p(-c^2) / 2 alpha).
  // The range of y grows like log(1 / n.v); beyond CHARLIE_PANEL_WIDTH it is cut into equal
  // sub-panels, so the rule keeps its resolution at extreme grazing (n.v down to 1e-7, where the
  // integrand has structure from cos = n.v up to cos ~ 1). Every cell of tables up to 256 wide
  // (n.v >= 1/512) has a single panel.
  const real y1 = log(cos1), y2 = log(sin1);
  if (sin_v > R(0.0) && y1 > y2) {
    const int n_sub = max(1, (int)ceil((y1 - y2) / CHARLIE_PANEL_WIDTH));
    const real h = (y1 - y2) / (real)n_sub;
    for (int p = 0; p < n_sub; ++p) {
      const real y0 = y2 + h * (real)p;
      DFG_NODES(k, n_xi) {
        const realv c = exp(y0 + h * vload_lanes(0, q + 2 * n_xi + k));
        const realv s = sqrt(fmax((R(1.0) - c) * (R(1.0) + c), R(0.0)));
        const realv density = e * exp(log1p(-c * c) * (R(0.5) / alpha)) * c * c;
        ACC_ADD(acc, panel_cut(n_dot_v, sin_v, s, c, h * density * vload_lanes(0, q + 3 * n_xi + k), alpha, q,
                               n_xi, n_phi));
      }
    }
  }
#else
  const real a2 = alpha * alpha;
  const real eta1 = a2 / (a2 + t1 * t1), eta2 = a2 / (a2 + R(1.0) / (t1 * t1));
  // Panel A: y = log(eta) from log(eta_1) up to 0; d xi = eta dy.
  const real ya = log(eta1);
  DFG_NODES(k, n_xi) {
    const realv eta = exp(ya * (R(1.0) - vload_lanes(0, q + k)));
    realv s, c;
    sample_ggx_ndf_polar_v(eta, alpha, &s, &c);
    ACC_ADD(acc, panel_full(n_dot_v, sin_v, s, c, -ya * eta * vload_lanes(0, q + n_xi + k), alpha, q, n_xi, n_phi));
  }
  // Panel B: y = log(eta) from log(eta_2) up to log(eta_1).
  const real yb = log(eta2);
  if (sin_v > R(0.0) && ya > yb) {
    DFG_NODES(k, n_xi) {
      const realv eta = exp(yb + (ya - yb) * vload_lanes(0, q + 2 * n_xi + k));
      realv s, c;
      sample_ggx_ndf_polar_v(eta, alpha, &s, &c);
      ACC_ADD(acc, panel_cut(n_dot_v, sin_v, s, c, (ya - yb) * eta * vload_lanes(0, q + 3 * n_xi + k), alpha,
                             q, n_xi, n_phi));
    }
  }
#endif
  // (1 / 2 pi) * 2 (mirror symmetry) = 1 / pi
  return acc_total(acc) * BRDFBAKE_INV_PI;
}

// ---------------------------------------------------------------------------------------------
// Monte Carlo estimators with Hammersley points.
// ---------------------------------------------------------------------------------------------
inline real2 lobe_monte_carlo(real n_dot_v, real sin_v, real alpha, uint samples) {
  const real3 v = (real3)(sin_v, R(0.0), n_dot_v);
  real2 acc = (real2)(R(0.0), R(0.0));
  for (uint i = (uint)DFG_FIRST; i < samples; i += (uint)DFG_STRIDE) {
    const real2 u = hammersley(i, samples);
#if defined(BRDFBAKE_LUT_CHARLIE)
#if defined(BRDFBAKE_EST_UNIFORM)
    // l uniform on the hemisphere, pdf 1 / (2 pi): weight D V n.l / pdf.
    const real3 l = sample_uniform_hemisphere(u);
    const real3 h = normalize(v + l);
#ifdef BRDFBAKE_SHEEN_NEUBELT
    const real vnl = V_Neubelt_times_nl(n_dot_v, l.z);
#else
    const real vnl = V_CharlieEstevezKulla_times_nl(n_dot_v, l.z, alpha);
#endif
    acc.x += D_Charlie(h.z, alpha) * vnl / pdf_uniform_hemisphere(l);
#else   // BRDFBAKE_EST_NDF: h with density D (n.h), weight V n.l 4 (v.h) / (n.h)
    const real3 h = sample_charlie_ndf(alpha, u);
    acc.x += charlie_weight(n_dot_v, sin_v, length(h.xy), h.z, h.x / max(length(h.xy), R(1e-30)), alpha);
#endif
#else  // GGX
#if defined(BRDFBAKE_EST_VNDF)
    // Heitz 2018: h with density G1(v) (v.h)+ D(h) / (n.v); the weight of l is G2 / G1(v).
    const real3 h = sample_ggx_vndf(v, alpha, u);
    const real v_dot_h = dot(v, h);
    const real n_dot_l = R(2.0) * v_dot_h * h.z - n_dot_v;
    if (n_dot_l > R(0.0) && v_dot_h > R(0.0)) {
      const real w = G2_SmithGGXCorrelated(n_dot_v, n_dot_l, alpha) / G1_SmithGGX(n_dot_v, alpha);
      const real fc = schlick_weight(v_dot_h);
      acc += (real2)((R(1.0) - fc) * w, fc * w);
    }
#else   // BRDFBAKE_EST_NDF: h with density D (n.h)
    const real3 h = sample_ggx_ndf(alpha, u);
    const real sin_h = length(h.xy);
    acc += ggx_weight(n_dot_v, sin_v, sin_h, h.z, sin_h > R(0.0) ? h.x / sin_h : R(1.0), alpha);
#endif
#endif
  }
  return acc / (real)samples;
}

// Burley's diffuse albedo by Gauss-Legendre in t = n.l and the midpoint rule in phi. After the phi
// integral the integrand is a polynomial of degree 8 in t (F_D90 is linear in cos(phi), the lobe
// quadratic), so 8 nodes in t and 4 on the half circle are exact up to rounding:
// albedo = (1/pi) int_0^1 t dt int_0^2pi dphi (pi f_d) = (1/2) sum_k w_k t_k sum_m g(t_k, phi_m).
inline real burley_albedo(real n_dot_v, real sin_v, real roughness, constant real* q, int n_xi,
                          int n_phi) {
  // the 8 nodes in t as the 8 lanes; cos((m + 1/2) pi / 4), m = 0..3, is +-cos(pi/8), +-cos(3 pi/8)
  const realv t = vload_lanes(0, q + 4 * n_xi + 3 * n_phi), w = vload_lanes(0, q + 4 * n_xi + 3 * n_phi + 8);
  const realv s = sqrt(fmax((realv)R(0.0), R(1.0) - t * t));
  const real cos_phi[4] = {R(0.92387953251128675613), R(0.38268343236508977173), R(-0.38268343236508977173),
                           R(-0.92387953251128675613)};
  realv row = (realv)R(0.0);
  for (int m = 0; m < 4; ++m) {
    const realv l_dot_v = s * (sin_v * cos_phi[m]) + t * n_dot_v;
    const realv l_dot_h2 = R(0.5) * (R(1.0) + l_dot_v);  // (l.h)^2 with h = (l + v)/|l + v|
    row += Fd_Burley_times_pi_v((realv)n_dot_v, t, sqrt(fmax(l_dot_h2, (realv)R(0.0))), roughness);
  }
  return R(0.5) * lanes_sum(w * t * row);
}

#ifdef BRDFBAKE_DFG_GROUPS
// The sum over the work-group of each work-item's v (the group's size a power of two), in `part`.
inline real2 dfg_group_sum(real2 v, local real2* part) {
  const int lid = (int)get_local_id(0);
  part[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int h = (int)get_local_size(0) / 2; h > 0; h >>= 1) {
    if (lid < h) part[lid] += part[lid + h];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  return part[0];
}
#endif

// The CPU shape: work-item (i, j) is cell (i, j). The GPU shape (BRDFBAKE_DFG_GROUPS): work-group
// (i, j) of BRDFBAKE_DFG_GROUP work-items along x is cell (i, j); the whole group shares the cell, so
// it returns (or not) together, before its barriers.
kernel void dfg_lut(global float* out, global const real* n_dot_vs, global const real* roughnesses,
                    const int width, const int height, const uint samples, constant real* q,
                    const int n_xi, const int n_phi) {
#ifdef BRDFBAKE_DFG_GROUPS
  local real2 part[BRDFBAKE_DFG_GROUP];
  const int i = (int)(get_global_id(0) / get_local_size(0)), j = (int)get_global_id(1);
#else
  const int i = (int)get_global_id(0), j = (int)get_global_id(1);
#endif
  if (i >= width || j >= height) return;
  // Inputs a hair outside [0,1] from upstream rounding are clamped; n.v = 0 exactly has no
  // defined reflection and stands for its limit (the smallest positive cosine kept).
  const real n_dot_v = clamp(n_dot_vs[i], BRDFBAKE_MIN_COSINE, R(1.0));
  const real sin_v = sqrt(max(R(0.0), (R(1.0) - n_dot_v) * (R(1.0) + n_dot_v)));
  const real roughness = clamp(roughnesses[j], R(0.0), R(1.0));
  const real alpha = max(roughness * roughness, BRDFBAKE_MIN_ALPHA);
#if defined(BRDFBAKE_EST_QUADRATURE)
  real2 lobe = lobe_quadrature(n_dot_v, sin_v, alpha, q, n_xi, n_phi);
#else
  real2 lobe = lobe_monte_carlo(n_dot_v, sin_v, alpha, samples);
#endif
#ifdef BRDFBAKE_DFG_GROUPS
  lobe = dfg_group_sum(lobe, part);
  if (get_local_id(0) != 0) return;
#endif
  const size_t texel = (size_t)j * (size_t)width + (size_t)i;
#if defined(BRDFBAKE_LUT_CHARLIE)
  out[texel] = (float)max(lobe.x, R(0.0));
#else
  const real diffuse = burley_albedo(n_dot_v, sin_v, roughness, q, n_xi, n_phi);
  real scale = max(lobe.x, R(0.0)), bias = max(lobe.y, R(0.0));
  // Energy conservation holds exactly (G2 <= 1); a sum a rounding error above 1 is scaled back.
  const real sum = scale + bias;
  if (sum > R(1.0)) {
    scale /= sum;
    bias /= sum;
  }
#if defined(BRDFBAKE_LUT_GGX_MULTISCATTER)
  out[3 * texel + 0] = (float)bias;
  out[3 * texel + 1] = (float)(scale + bias);
#else
  out[3 * texel + 0] = (float)scale;
  out[3 * texel + 1] = (float)bias;
#endif
  out[3 * texel + 2] = (float)diffuse;
#endif
}
