// The reference render of a material preview (host/src/families/preview/): for each pixel of a
// sphere, the converged integrals of the GGX lobe and the cosine against the environment,
//   S1 = int D V (n.l)+ L dl,   S2 = int D V Fc (n.l)+ L dl,   Irr = int (n.l)+ L dl,
// D = GGX (Walter et al. 2007, eq. 33), V = G2 / (4 n.l n.v) with the height-correlated Smith G2
// (Heitz 2014, eq. 99), Fc = (1 - v.h)^5, so that the specular radiance with Schlick's Fresnel is
// F0 S1 + (1 - F0) S2 (the host combines them with the target's compensation and diffuse weight,
// host/src/families/preview/shading.cpp). No split sum, no prefiltering, no storage.
//
// The environment's continuous model: every pixel of the equirect image is constant over its cell
// of longitude x latitude (the model the SH projection uses too; docs/PREVIEW.md). The integrals
// are sums over a partition of the sphere into cells of a quadtree over the image (built on the
// host in double, host/src/families/preview/tree.cpp): level 0 holds the pixels, level k + 1 the
// sums of 2 x 2 cells of level k, each cell with its solid angle Omega, its mean direction g (unit,
// and the mean's length), its angular radius rho (the largest angle from g to the cell), L Omega and
// the channels' first moments int l L_c dl. Below level 0 a pixel is split further on the fly into
// 2^s x 2^s sub-cells of the same radiance (exact geometry). The brightest pixels (the prefilter's
// environment sampling: above 16 x the mean, at most 256) are not in the tree's radiance: each is
// walked on its own, from the pixel down, into the radiance sums only.
//
// The walk (one work-item a pixel): from every cell of a start level (at most 64 x 32), a cell is
// replaced by its four children (depth first) while the integrand varies too much across it:
//   the lobe's peak   within (refinement + 1) rho of the reflected direction r, while rho is above
//                     the lobe's narrowest width / refinement: the GGX lobe of half vectors of width
//                     alpha maps to directions 2 alpha wide in the plane of incidence and 2 alpha v.h
//                     across it (dl = 4 (v.h) dh), v.h ~ n.v at the peak: 2 alpha n.v;
//   the horizon of n  a cell that straddles it (|n.g| < rho), while rho > horizon_size or its
//                     luminance x rho exceeds horizon_energy (a sun at the terminator is cut finely);
//   any cell          with rho > max_size.
// A cell that is not refined contributes:
//   to the irradiance, (n.M_c)+ per channel: exact for a cell wholly above or below the horizon
//     (n.l is linear in l);
//   to the lobe, for a pixel or a sub-cell (constant radiance) the 2 x 2 Gauss-Legendre rule over its
//     rectangle (fourth order); for a cell of varying radiance the lobe at its luminance centroid
//     (the first moment: second order even across an edge in the image), near the peak with the
//     Gauss rule's weight shifted there.
// Each cell is counted once by construction.
//
// Normalisation (the ratio estimator of kernels/prefilter.cl): the same walk sums the lobes' own
// quadrature G1 = sum of the lobe's weights over the cells (at g, or the Gauss rule), likewise G2,
// and Gd = sum (n.g)+ |g| Omega, whose exact values are known (the directional albedos A = int D V n.l
// and B = int D V Fc n.l, computed by the DFG family's quadrature at this pixel's n.v and alpha, and
// pi). The result is
//   S1 = N1 A / G1,  S2 = N2 B / G2,  Irr = Nd pi / Gd,
// so a constant environment comes back exactly (the white furnace), and where a lobe is narrower
// than the cells the ratio tends to the radiance of the cells under it times the albedo.
//
// The sheen lobe (KHR_materials_sheen; a pixel's lobe flag 1): the same walk and normalisation with
// D = D_Charlie (Estevez & Kulla 2017) and their fitted visibility (common/charlie.clh, the charlie
// DFG table's default), A = the charlie table's albedo E(n.v), B = 0 (S2 is not used). The lobe has
// no peak at r (it lies along the horizon of n, as wide as sqrt(alpha) there): no refinement near r,
// the horizon's rules resolve it.
//
// The iridescent lobe (KHR_materials_iridescence; a pixel's lobe flag 2, only where the program is
// built with PREVIEW_IRIDESCENCE: glTF materials decide which lobes the kernel is compiled with):
// the GGX lobe times the thin-film Fresnel F_irid(v.h) of common/thin_film.clh, per channel (the film
// is not linear in (S1, S2) as Schlick's Fresnel is):
//   S1_c = int D V F_irid,c(v.h) (n.l)+ L_c dl,
// the film's thickness, index and base F0 given per pixel (films). The same walk and refinement as
// the GGX lobe (F_irid varies slowly over v.h, where D is narrow); the normalisation is the GGX
// lobe's, S1 = N1 A / G1 with G1 the quadrature's sum of D V n.l (without the film), so that the
// film's weights share the cells' solid-angle error that A / G1 removes. S2 = 0.
//
// Roughness 0 (alpha = 0) is a delta: S1 = L(r) and S2 = (1 - n.v)^5 L(r), the radiance of the
// pixel r falls in, exactly (the iridescent lobe: F_irid(n.v) L(r)); only the irradiance is walked.
#include "common/real.clh"
#include "common/charlie.clh"
#ifdef PREVIEW_IRIDESCENCE
#include "common/thin_film.clh"
#endif

#define PREVIEW_STACK 192     // entries of the depth-first stack (3 per level below the start is plenty)
#define PREVIEW_MAX_SUB 8     // sub-cell levels below a pixel (1/256 of a pixel a side)

typedef struct {
  real3 n, v, r;
  real nv;      // n.v
  real a2;      // alpha^2
  real lv;      // sqrt(n.v^2 (1 - alpha^2) + alpha^2), V's view term
  real peak;    // the lobe's peak region: refine within this many rho of r (refinement + 1)
  real width;   // refine near r while rho > width (2 alpha / refinement)
  int spec;     // alpha > 0
  int sheen;    // the Charlie lobe (alpha = its alpha) instead of GGX
  real alpha;
  CharlieFit fit;   // the sheen's fitted Lambda at alpha (charlie_fit)
  real lambda_v1;   // 1 + Lambda(n.v)
#ifdef PREVIEW_IRIDESCENCE
  int film;            // the GGX lobe times the thin-film Fresnel (KHR_materials_iridescence)
  real film_thickness;  // nm
  real film_ior;
  real3 film_base_f0;
#endif
} PreviewPixel;

typedef struct {
  real n1[3], n2[3], nd[3];
  real g1, g2, gd;
} PreviewSums;

// ---- The lobe ---------------------------------------------------------------------------------------

// D V (n.l)+ and the same times Fc at a unit direction l. D with sin^2 and cos^2 of the half vector
// taken from the unnormalised h = v + l: sin^2 = |n x h|^2 / |h|^2 (no cancellation near the peak,
// where 1 - (n.h)^2 would lose the few digits a narrow lobe needs), so
//   D = alpha^2 / (pi (sin^2 + alpha^2 cos^2)^2) = alpha^2 |h|^4 / (pi (|n x h|^2 + alpha^2 (n.h)^2)^2).
// V: Heitz 2014, eq. 99, V = 0.5 / (n.l sqrt(n.v^2 (1 - a^2) + a^2) + n.v sqrt(n.l^2 (1 - a^2) + a^2)).
// v.h = |h| / 2 (v and l are unit).
inline real2 preview_lobe(const PreviewPixel* p, real3 l) {
  const real nl = dot(p->n, l);
  if (!(nl > R(0.0))) return (real2)(R(0.0));
  const real3 h = p->v + l;
  const real3 c = cross(p->n, h);
  const real nh = dot(p->n, h), h2 = dot(h, h);
  if (p->sheen) {
    if (!(h2 > R(0.0))) return (real2)(R(0.0));
    // V_CharlieEstevezKulla_times_nl with the view's Lambda and the fit computed once a pixel
    const real x = fmin(nl, R(1.0));
    const real ll = x < R(0.5) ? exp(charlie_L(p->fit, x)) : exp(R(2.0) * p->fit.l_half - charlie_L(p->fit, R(1.0) - x));
    const real g = D_Charlie(nh / sqrt(h2), p->alpha) / ((p->lambda_v1 + ll) * R(4.0) * p->nv);
    return (real2)(g, R(0.0));
  }
  const real t = dot(c, c) + p->a2 * nh * nh;
  if (!(t > R(0.0))) return (real2)(R(0.0));
  const real d = p->a2 * h2 * h2 / (BRDFBAKE_PI * t * t);
  const real vis = R(0.5) / (nl * p->lv + p->nv * sqrt(nl * nl * (R(1.0) - p->a2) + p->a2));
  const real g = d * vis * nl;
  const real f = fmax(R(1.0) - R(0.5) * sqrt(h2), R(0.0));
  const real f2 = f * f;
  return (real2)(g, g * f2 * f2 * f);
}

// Whether the angle between unit a and b is below theta (a cross product, not 1 - a.b, for small
// angles: fp32 resolves angles far below 3e-4 rad that way).
inline bool preview_within(real3 a, real3 b, real theta) {
  const real c = dot(a, b);
  if (theta >= R(0.5) * BRDFBAKE_PI) return c > cos(theta);
  if (!(c > R(0.0))) return false;
  const real3 x = cross(a, b);
  const real s = sin(theta);
  return dot(x, x) < s * s;
}

// ---- Cells ----------------------------------------------------------------------------------------

// A cell as the tree stores it (20 floats, host/src/families/preview/tree.hpp): its unit mean
// direction g and the mean's length |int l dl| / Omega, Omega, its angular radius rho, L Omega and
// its luminance, and the first moments M_c = int l L_c dl of the three channels. A pixel or a
// sub-cell is constant (its L is one value): its rectangle in (u, v) is kept for the lobe's rule.
typedef struct {
  real3 g;      // unit
  real gl;      // |mean direction| <= 1
  real omega;
  real rho;
  real lo[3];   // L Omega
  real lum;     // luminance of L Omega
  real3 mo[3];  // int l L_c dl, c = r, g, b
  int is_constant;
  real uc, du, vc, dv;  // a constant cell's rectangle
} PreviewCell;

inline PreviewCell preview_tree_cell(global const float* tree, constant int4* levels, int k, int i) {
  global const float* p = tree + 20 * ((size_t)levels[k].x + (size_t)i);
  const float16 a = vload16(0, p);
  const float4 b = vload4(0, p + 16);
  PreviewCell c;
  c.g = (real3)((real)a.s0, (real)a.s1, (real)a.s2);
  c.gl = (real)a.s3;
  c.omega = (real)a.s4;
  c.rho = (real)a.s5;
  c.lo[0] = (real)a.s6;
  c.lo[1] = (real)a.s7;
  c.lo[2] = (real)a.s8;
  c.lum = (real)a.s9;
  c.mo[0] = (real3)((real)a.sa, (real)a.sb, (real)a.sc);
  c.mo[1] = (real3)((real)a.sd, (real)a.se, (real)a.sf);
  c.mo[2] = (real3)((real)b.s0, (real)b.s1, (real)b.s2);
  c.is_constant = 0;
  return c;
}

// The geometry of the cell of u in [uc - du / 2, uc + du / 2], v in [vc - dv / 2, vc + dv / 2] of the
// equirect (docs/CONVENTIONS.md: longitude phi = 2 pi (0.5 - u), latitude theta = pi (0.5 - v),
// direction (sin phi cos theta, sin theta, cos phi cos theta)), given by its centre and size so that
// a sub-cell a few hundredths of a pixel wide keeps its digits in fp32, and with the differences of
// sines written as products for the same reason:
//   Omega = dphi (sin tb - sin ta) = dphi 2 cos(tm) sin(dt / 2),
//   int l dl = (2 sin(pm) sin(dphi / 2) Q, dphi (sin^2 tb - sin^2 ta) / 2, 2 cos(pm) sin(dphi / 2) Q),
//   Q = int cos^2 = (dt + cos(2 tm) sin(dt)) / 2.
// rho is the half diagonal (dt / 2, dphi cos(t) / 2 at the cell's wider edge) with a margin: the
// cells here are below a pixel, where the sphere is flat to far better than the margin.
inline void preview_rect(real uc, real du, real vc, real dv, PreviewCell* c) {
  const real dphi = R(2.0) * BRDFBAKE_PI * du, pm = R(2.0) * BRDFBAKE_PI * (R(0.5) - uc);
  const real dt = BRDFBAKE_PI * dv, tm = BRDFBAKE_PI * (R(0.5) - vc);
  const real sh = sin(R(0.5) * dphi);
  const real ds = R(2.0) * cos(tm) * sin(R(0.5) * dt);   // sin tb - sin ta
  const real ss = R(2.0) * sin(tm) * cos(R(0.5) * dt);   // sin tb + sin ta
  const real q = R(0.5) * (dt + cos(R(2.0) * tm) * sin(dt));
  c->omega = dphi * ds;
  const real3 integral = (real3)(R(2.0) * sin(pm) * sh * q, R(0.5) * dphi * ds * ss, R(2.0) * cos(pm) * sh * q);
  const real len = length(integral);
  c->g = len > R(0.0) ? integral / len : (real3)(R(0.0), R(1.0), R(0.0));
  c->gl = c->omega > R(0.0) ? len / c->omega : R(0.0);
  c->mo[0] = c->mo[1] = c->mo[2] = integral;  // times L_c by the caller
  c->is_constant = 1;
  c->uc = uc;
  c->du = du;
  c->vc = vc;
  c->dv = dv;
  const real wide = fmax(cos(tm - R(0.5) * dt), cos(tm + R(0.5) * dt));
  const real a = R(0.5) * dt, b = R(0.5) * dphi * wide;
  c->rho = R(1.02) * sqrt(a * a + b * b);
}

// Pixel (x, y) of level 0 from its quadtree index (the Morton order of host/src/families/preview/
// opencl.cpp: root x >> top, then x and y interleaved, x in the even bits).
inline int preview_compact(int v) {
  v &= 0x55555555;
  v = (v | (v >> 1)) & 0x33333333;
  v = (v | (v >> 2)) & 0x0F0F0F0F;
  v = (v | (v >> 4)) & 0x00FF00FF;
  v = (v | (v >> 8)) & 0x0000FFFF;
  return v;
}

// ---- The walk ---------------------------------------------------------------------------------------

typedef struct {
  real horizon_size;    // refine straddling cells larger than this (radians)
  real horizon_energy;  // ... or whose luminance(L Omega) x rho exceeds this
  real max_size;        // refine every cell larger than this
} PreviewRules;

// Whether cell c is to be replaced by its children for pixel p. No trigonometry: sin(rho) <= rho
// makes the horizon's band and the peak's region slightly wider than the angles say (refining a
// little more, never less).
inline bool preview_refine(const PreviewPixel* p, const PreviewRules* rules, const PreviewCell* c) {
  if (c->rho > rules->max_size) return true;
  const real ng = dot(p->n, c->g);
  if (ng < -c->rho) return false;  // wholly below the horizon: nothing to resolve
  if (p->spec && c->rho > p->width) {
    const real t = p->peak * c->rho, cr = dot(c->g, p->r);
    if (t >= R(1.5)) {
      if (cr > cos(t)) return true;
    } else if (cr > R(0.0)) {
      const real3 x = cross(c->g, p->r);
      if (dot(x, x) < t * t) return true;
    }
  }
  return fabs(ng) < c->rho && (c->rho > rules->horizon_size || c->lum * c->rho > rules->horizon_energy);
}

// The lobe over a constant cell by the 2 x 2 Gauss-Legendre product rule in longitude and latitude
// (dl = cos(theta) dtheta dphi): fourth order in the cell's size, where the moment rule is second;
// returns (sum w D V n.l, sum w D V Fc n.l) with the weights w summing to about Omega.
inline real2 preview_lobe_gauss(const PreviewPixel* p, const PreviewCell* c) {
  const real k = R(0.28867513459481288);  // 1 / (2 sqrt(3)): the nodes at +-1/sqrt(3) of the half width
  const real dphi = R(2.0) * BRDFBAKE_PI * c->du, dt = BRDFBAKE_PI * c->dv;
  real2 sum = (real2)(R(0.0));
  for (int j = 0; j < 2; ++j) {
    const real t = BRDFBAKE_PI * (R(0.5) - (c->vc + (j ? k : -k) * c->dv));
    const real ct = cos(t), st = sin(t);
    const real w = R(0.25) * dphi * dt * ct;
    for (int i = 0; i < 2; ++i) {
      const real f = R(2.0) * BRDFBAKE_PI * (R(0.5) - (c->uc + (i ? k : -k) * c->du));
      sum += w * preview_lobe(p, (real3)(sin(f) * ct, st, cos(f) * ct));
    }
  }
  return sum;
}

#ifdef PREVIEW_IRIDESCENCE
// The iridescent lobe at a unit direction l: (D V (n.l)+, the same times F_irid,c(v.h) for c = r, g,
// b), the film over its base seen from the outside medium (index 1: air, as the extension's
// evalIridescence(outsideIor 1, ...)).
inline real4 preview_lobe_film(const PreviewPixel* p, real3 l) {
  const real g = preview_lobe(p, l).x;
  if (!(g > R(0.0))) return (real4)(R(0.0));
  const real vh = R(0.5) * length(p->v + l);
  const real3 f = thin_film_fresnel_fast(vh, p->film_thickness, R(1.0), p->film_ior, p->film_base_f0);
  return (real4)(g, g * f.x, g * f.y, g * f.z);
}

// preview_lobe_gauss for the iridescent lobe: (sum w D V n.l, the same times F_irid,c), the film's
// Fresnel taken at the cell's centre g (it varies over v.h on the scale of the film's fringes, tenths
// of a radian, where a constant cell is below a pixel: one thin-film evaluation a cell, not four).
inline real4 preview_lobe_film_gauss(const PreviewPixel* p, const PreviewCell* c) {
  const real g = preview_lobe_gauss(p, c).x;
  const real vh = R(0.5) * length(p->v + c->g);
  const real3 f = thin_film_fresnel_fast(vh, p->film_thickness, R(1.0), p->film_ior, p->film_base_f0);
  return (real4)(g, g * f.x, g * f.y, g * f.z);
}

// preview_add's lobe part for the iridescent lobe: the same rules (the Gauss rule on a constant
// cell; the luminance centroid on a varying one, the Gauss rule's weight near the peak), per channel.
inline void preview_add_film(const PreviewPixel* p, const PreviewCell* c, PreviewSums* s, bool numerator) {
  real weight;  // the lobe's integral over the cell per unit radiance (D V n.l: the normalisation's)
  real3 at_m;   // the film-weighted lobe per unit L Omega, per channel
  if (c->is_constant) {
    const real4 gauss = preview_lobe_film_gauss(p, c);
    weight = gauss.x;
    at_m = gauss.yzw / fmax(c->omega, R(1e-30));
  } else {
    const real at_g = preview_lobe(p, c->g).x;
    const real3 m = R(0.2126) * c->mo[0] + R(0.7152) * c->mo[1] + R(0.0722) * c->mo[2];
    const real ml = length(m);
    at_m = preview_lobe_film(p, ml > R(0.0) ? m / ml : c->g).yzw;
    weight = at_g * c->omega;
    if (preview_within(c->g, p->r, R(2.0) * p->peak * c->rho)) {
      const real4 gauss = preview_lobe_film_gauss(p, c);
      at_m = at_g > R(1e-3) * gauss.x / c->omega ? at_m * (gauss.x / weight) : gauss.yzw / c->omega;
      weight = gauss.x;
    }
  }
  s->n1[0] += at_m.x * c->lo[0];
  s->n1[1] += at_m.y * c->lo[1];
  s->n1[2] += at_m.z * c->lo[2];
  if (numerator) return;
  s->g1 += weight;
}
#endif

// One cell's contribution (see the top of the file): the cosine at the channels' first moments
// (exact for a cell wholly above the horizon: n.l is linear); the lobe at the luminance-weighted
// mean m, and for the normalisation at g. A constant cell (a pixel, a sub-cell) takes the lobe by
// preview_lobe_gauss instead. Near the lobe's peak (within twice the refinement region, where its
// curvature is largest) a cell of varying radiance takes the same rule's value for the lobe's
// weight, shifted to m by the ratio lobe(m) / lobe(g): exact for a constant radiance, and still
// first-order right where the radiance varies.
// `numerator`: add to the radiance sums only (a bright pixel: its solid angle is already in the
// tree's normalisation sums, where it stays with no radiance).
inline void preview_add(const PreviewPixel* p, const PreviewCell* c, PreviewSums* s, bool numerator) {
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    const real nm = fmax(dot(p->n, c->mo[k]), R(0.0));
    s->nd[k] += nm;
    any = any || nm > R(0.0);
  }
  const real ng = fmax(dot(p->n, c->g), R(0.0)) * c->gl * c->omega;
  if (!numerator) s->gd += ng;
  if (!p->spec || (!any && ng <= R(0.0))) return;
#ifdef PREVIEW_IRIDESCENCE
  if (p->film) {
    preview_add_film(p, c, s, numerator);
    return;
  }
#endif
  real2 weight;  // the lobe's integral over the cell, per unit radiance
  real2 at_m;    // the lobe's value for the radiance, per unit L Omega
  if (c->is_constant) {
    weight = preview_lobe_gauss(p, c);
    at_m = weight / fmax(c->omega, R(1e-30));
  } else {
    const real2 at_g = preview_lobe(p, c->g);
    const real3 m = R(0.2126) * c->mo[0] + R(0.7152) * c->mo[1] + R(0.0722) * c->mo[2];
    const real ml = length(m);
    at_m = ml > R(0.0) ? preview_lobe(p, m / ml) : at_g;
    weight = at_g * c->omega;
    if (preview_within(c->g, p->r, R(2.0) * p->peak * c->rho)) {
      const real2 gauss = preview_lobe_gauss(p, c);
      at_m.x = at_g.x > R(1e-3) * gauss.x / c->omega ? at_m.x * gauss.x / weight.x : gauss.x / c->omega;
      at_m.y = at_g.y > R(1e-3) * gauss.y / c->omega ? at_m.y * gauss.y / weight.y : gauss.y / c->omega;
      weight = gauss;
    }
  }
  for (int k = 0; k < 3; ++k) {
    s->n1[k] += at_m.x * c->lo[k];
    s->n2[k] += at_m.y * c->lo[k];
  }
  if (numerator) return;
  s->g1 += weight.x;
  s->g2 += weight.y;
}

// A stack entry: a cell of level k >= 0 (a = its index), or a sub-cell of pixel a (k = -1 - packed,
// packed = (s - 1) | sx << 4 | sy << 14: level s >= 1 below the pixel, position sx, sy < 2^s).
typedef struct {
  int a, k;
} PreviewRef;

// The cell of stack entry e, or its child q (0..3; q < 0: e itself). Sub-cells below a pixel take
// its radiance: `fixed` when given (a bright pixel), else the pixel's cell of the tree.
inline PreviewCell preview_cell(PreviewRef e, int q, PreviewRef* ref, global const float* tree, constant int4* levels,
                                int top, int image_w, int image_h, const real* fixed) {
  PreviewCell c;
  if (!fixed && (q < 0 || e.k > 0)) {
    *ref = q < 0 ? e : (PreviewRef){4 * e.a + q, e.k - 1};
    c = preview_tree_cell(tree, levels, ref->k, ref->a);
    // its rectangle in (u, v), clipped to the image; a pixel is constant
    const int bits = top - ref->k;
    const int root = ref->a >> (2 * bits), rem = ref->a & ((1 << (2 * bits)) - 1);
    const int x = (root << bits) | preview_compact(rem), y = preview_compact(rem >> 1);
    const int x0 = x << ref->k, y0 = y << ref->k;
    const int x1 = min((x + 1) << ref->k, image_w), y1 = min((y + 1) << ref->k, image_h);
    c.is_constant = ref->k == 0;
    c.du = (real)(x1 - x0) / (real)image_w;
    c.dv = (real)(y1 - y0) / (real)image_h;
    c.uc = R(0.5) * (real)(x0 + x1) / (real)image_w;
    c.vc = R(0.5) * (real)(y0 + y1) / (real)image_h;
    return c;
  }
  // a pixel (the entry itself, fixed), or a pixel's (e.k == 0) or a sub-cell's (e.k < 0) sub-cells
  const int pixel = e.a;
  int sub = 0, sx = 0, sy = 0;
  if (q < 0) {
    sub = 0;
  } else if (e.k == 0) {
    sub = 1;
    sx = q & 1;
    sy = q >> 1;
  } else {
    const int packed = -1 - e.k;
    sub = (packed & 15) + 2;  // one below the parent's
    sx = 2 * ((packed >> 4) & 1023) + (q & 1);
    sy = 2 * ((packed >> 14) & 1023) + (q >> 1);
  }
  const int root = pixel >> (2 * top), rem = pixel & ((1 << (2 * top)) - 1);
  const int pixel_x = (root << top) | preview_compact(rem), pixel_y = preview_compact(rem >> 1);
  const real scale = R(1.0) / (real)(1 << sub);
  preview_rect(((real)pixel_x + ((real)sx + R(0.5)) * scale) / (real)image_w, scale / (real)image_w,
               ((real)pixel_y + ((real)sy + R(0.5)) * scale) / (real)image_h, scale / (real)image_h, &c);
  real l[3];
  if (fixed) {
    for (int k = 0; k < 3; ++k) l[k] = fixed[k];
  } else {
    const PreviewCell leaf = preview_tree_cell(tree, levels, 0, pixel);
    for (int k = 0; k < 3; ++k) l[k] = leaf.omega > R(0.0) ? leaf.lo[k] / leaf.omega : R(0.0);
  }
  for (int k = 0; k < 3; ++k) {
    c.lo[k] = l[k] * c.omega;
    c.mo[k] *= l[k];
  }
  c.lum = R(0.2126) * c.lo[0] + R(0.7152) * c.lo[1] + R(0.0722) * c.lo[2];
  *ref = sub == 0 ? (PreviewRef){pixel, 0} : (PreviewRef){pixel, -1 - ((sub - 1) | (sx << 4) | (sy << 14))};
  return c;
}

// The depth-first walk from one root entry; returns false when the stack overflowed (a cell was
// summed unrefined).
inline bool preview_walk(const PreviewPixel* p, const PreviewRules* rules, PreviewRef root, const real* fixed,
                         global const float* tree, constant int4* levels, int top, int image_w, int image_h,
                         PreviewSums* s, int* visited) {
  PreviewRef stack[PREVIEW_STACK];
  bool ok = true;
  int top_of_stack = 0;
  stack[top_of_stack++] = root;
  bool first = true;
  while (top_of_stack > 0) {
    const PreviewRef e = stack[--top_of_stack];
    // the cells to look at: the root itself, else the four children of e
    const int n_cells = first ? 1 : 4;
    for (int q = 0; q < n_cells; ++q) {
      PreviewRef ref;
      const PreviewCell c = preview_cell(e, first ? -1 : q, &ref, tree, levels, top, image_w, image_h, fixed);
      if (!(c.omega > R(0.0))) continue;  // padding beyond the image
      ++*visited;
      const bool deeper = ref.k >= 0 || ((-1 - ref.k) & 15) + 1 < PREVIEW_MAX_SUB;
      if (deeper && preview_refine(p, rules, &c)) {
        if (top_of_stack < PREVIEW_STACK) {
          stack[top_of_stack++] = ref;
          continue;
        }
        ok = false;  // summed as it is
      }
      preview_add(p, &c, s, fixed != 0);
    }
    first = false;
  }
  return ok;
}

// params: view (x, y, z), refinement, horizon_size, horizon_energy, max_size.
// pixels: 8 floats a pixel: n (x, y, z), alpha, A, B (the exact directional albedos), the lobe (0 GGX,
// 1 the Charlie sheen lobe, 2 GGX times the thin film: PREVIEW_IRIDESCENCE only), 0.
// films: 8 floats a pixel (read for lobe 2 only; one element where no pixel has a film): the film's
// thickness (nm), its index, the base's F0 (r, g, b), 0, 0, 0.
// out: 12 reals a pixel: S1 (rgb), S2 (rgb), Irr (rgb), cells visited, overflow (0 or 1), 0.
// levels[k] = (first cell in tree, cell count, grid width, grid height), 16 floats a cell; start: the
// first level walked;
// top: log2 of the width in cells of level 0's root squares (the grid of level 0 is 2^(top+1) x 2^top).
kernel void preview_reference(global real* out, global const float* pixels, int n_pixels, constant real* params,
                              global const float* tree, constant int4* levels, int start, int top, int image_w,
                              int image_h, global const float* image, global const int* bright_index,
                              global const float* bright_rgb, int n_bright, global const float* films) {
  const int id = (int)get_global_id(0);
  if (id >= n_pixels) return;
  global const float* px = pixels + 8 * (size_t)id;
  PreviewPixel p;
  p.n = normalize((real3)((real)px[0], (real)px[1], (real)px[2]));
  p.v = (real3)(params[0], params[1], params[2]);
  const real alpha = (real)px[3];
  const real albedo = (real)px[4], bias = (real)px[5];
  p.nv = fmax(dot(p.n, p.v), R(1e-7));
  p.r = normalize(R(2.0) * p.nv * p.n - p.v);
  p.a2 = alpha * alpha;
  p.lv = sqrt(p.nv * p.nv * (R(1.0) - p.a2) + p.a2);
  p.peak = params[3] + R(1.0);
  // the lobe's narrowest width: across the plane of incidence a half vector's tilt of alpha turns l
  // by 2 alpha (v.h), v.h ~ n.v at the peak (dl = 4 (v.h) dh): thin at grazing view
  p.width = R(2.0) * alpha * p.nv / params[3];
  p.spec = alpha > R(0.0);
  p.sheen = px[6] == 1.0f;
  p.alpha = alpha;
#ifdef PREVIEW_IRIDESCENCE
  p.film = px[6] == 2.0f;
  if (p.film) {
    global const float* fp = films + 8 * (size_t)id;
    p.film_thickness = (real)fp[0];
    p.film_ior = (real)fp[1];
    p.film_base_f0 = (real3)((real)fp[2], (real)fp[3], (real)fp[4]);
  }
#else
  (void)films;
#endif
  if (p.sheen) {
    p.width = INFINITY;  // no peak at r: the horizon's rules resolve the sheen lobe
    p.fit = charlie_fit(alpha);
    p.lambda_v1 = R(1.0) + Lambda_CharlieEstevezKulla(p.nv, alpha);
  }
  PreviewRules rules;
  rules.horizon_size = params[4];
  rules.horizon_energy = params[5];
  rules.max_size = params[6];

  PreviewSums s;
  for (int k = 0; k < 3; ++k) s.n1[k] = s.n2[k] = s.nd[k] = R(0.0);
  s.g1 = s.g2 = s.gd = R(0.0);
  int visited = 0;
  bool ok = true;
  const int n_start = levels[start].z * levels[start].w;
  for (int i0 = 0; i0 < n_start; ++i0)
    ok &= preview_walk(&p, &rules, (PreviewRef){i0, start}, 0, tree, levels, top, image_w, image_h, &s, &visited);
  for (int b = 0; b < n_bright; ++b) {
    const real l[3] = {(real)bright_rgb[3 * b], (real)bright_rgb[3 * b + 1], (real)bright_rgb[3 * b + 2]};
    ok &= preview_walk(&p, &rules, (PreviewRef){bright_index[b], 0}, l, tree, levels, top, image_w, image_h, &s, &visited);
  }

  global real* o = out + 12 * (size_t)id;
  if (p.spec) {
    const real k1 = s.g1 > R(0.0) ? albedo / s.g1 : R(0.0), k2 = s.g2 > R(0.0) ? bias / s.g2 : R(0.0);
    for (int k = 0; k < 3; ++k) {
      o[k] = s.n1[k] * k1;
      o[3 + k] = s.n2[k] * k2;
    }
  } else {
    // the mirror: the pixel r falls in (longitude, latitude as docs/CONVENTIONS.md)
    const real u = R(0.5) - atan2(p.r.x, p.r.z) * (R(0.5) * BRDFBAKE_INV_PI);
    const real v = R(0.5) - asin(clamp(p.r.y, R(-1.0), R(1.0))) * BRDFBAKE_INV_PI;
    const int x = clamp((int)floor(u * (real)image_w), 0, image_w - 1);
    const int y = clamp((int)floor(v * (real)image_h), 0, image_h - 1);
    global const float* l = image + 3 * ((size_t)y * (size_t)image_w + (size_t)x);
    const real f = R(1.0) - p.nv, f2 = f * f, fc = f2 * f2 * f;
    for (int k = 0; k < 3; ++k) {
      o[k] = (real)l[k];
      o[3 + k] = fc * (real)l[k];
    }
#ifdef PREVIEW_IRIDESCENCE
    if (p.film) {
      // the mirror's half vector is n: F_irid(n.v)
      const real3 fi = thin_film_fresnel_fast(p.nv, p.film_thickness, R(1.0), p.film_ior, p.film_base_f0);
      o[0] *= fi.x;
      o[1] *= fi.y;
      o[2] *= fi.z;
      o[3] = o[4] = o[5] = R(0.0);
    }
#endif
  }
  const real kd = s.gd > R(0.0) ? BRDFBAKE_PI / s.gd : R(0.0);
  for (int k = 0; k < 3; ++k) o[6 + k] = s.nd[k] * kd;
  o[9] = (real)visited;
  o[10] = ok ? R(0.0) : R(1.0);
  o[11] = R(0.0);
}
