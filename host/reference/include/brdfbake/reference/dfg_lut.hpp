// Scalar double-precision reference for the split-sum DFG lookup tables.
//
// Written from the papers, independently of kernels/dfg_lut.cl. Integrals are computed by
// deterministic composite Gauss-Legendre quadrature, converged to better than 1e-6 absolute.
// Conventions (docs/CONVENTIONS.md): perceptual roughness in [0,1], GGX alpha = roughness^2,
// Charlie alpha = sheen_roughness^2, n_dot_v in [0,1].
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace brdfbake::reference {

// Resolution of the composite Gauss-Legendre rules (src/dfg_lut.cpp describes the panels): `order` nodes
// per panel; `refinement` f divides every panel width by f and deepens every geometric refinement
// by f^2. The defaults meet the 1e-6 contract with a wide margin; convergence is checked against
// {2 * order, 2 * refinement}.
struct Quadrature {
  int order = 10;      // in [1, 512]
  int refinement = 1;  // in [1, 64]
};

// Split-sum scale and bias (Karis 2013) of the GGX specular lobe with height-correlated Smith
// visibility (Heitz 2014): integral of f_spec * n_dot_l = F0 * scale + F90 * bias for
// Schlick's Fresnel F = F0 + (F90 - F0) (1 - v.h)^5.
struct DfgGgx {
  double scale;
  double bias;
};
DfgGgx dfg_ggx(double n_dot_v, double roughness);
DfgGgx dfg_ggx(double n_dot_v, double roughness, const Quadrature& quadrature);

// Directional albedo of Burley's (Disney 2012) diffuse lobe, integral of f_d * n_dot_l with
// f_d = (1/pi) (1 + (F_D90 - 1)(1 - n.l)^5)(1 + (F_D90 - 1)(1 - n.v)^5),
// F_D90 = 0.5 + 2 roughness (l.h)^2, roughness perceptual (as Burley's parameter).
double burley_albedo(double n_dot_v, double roughness);
double burley_albedo(double n_dot_v, double roughness, const Quadrature& quadrature);
// The same lobe with F_D90 held fixed instead of depending on l.h (for identities: F_D90 = 1 is
// Lambert, and the albedo is (1 + (F_D90 - 1)(1 - n.v)^5)(1 + (F_D90 - 1)/21) in closed form).
double burley_albedo_fixed_f90(double n_dot_v, double f_d90, const Quadrature& quadrature = {});

// Which visibility term the Charlie sheen lobe uses.
enum class SheenVisibility {
  EstevezKulla,  // Estevez & Kulla 2017, fitted Lambda (the glTF KHR_materials_sheen choice)
  Neubelt,       // Neubelt & Pettineo 2013, 1 / (4 (n.l + n.v - n.l n.v)) (Filament's choice)
};

// Directional albedo of the Charlie sheen lobe: integral of D_charlie(h) V(l, v) n_dot_l over the
// hemisphere (sheen colour 1, no Fresnel).
double charlie_albedo(double n_dot_v, double sheen_roughness, SheenVisibility visibility);
double charlie_albedo(double n_dot_v, double sheen_roughness, SheenVisibility visibility, const Quadrature& quadrature);

// Whole tables, texel (i, j) at the cell centre n_dot_v = (i+0.5)/width, roughness = (j+0.5)/height.
// Row-major, j outer, `channels` floats per texel (see each function). threads = 0: all cores.
enum class LutKind { Ggx, GgxMultiscatter, Charlie };
// Ggx:             scale, bias, burley_albedo                        (3 channels)
// GgxMultiscatter: bias (sum Fc V), albedo (sum V = scale + bias), burley_albedo (3 channels)
// Charlie:         albedo                                            (1 channel)
int lut_channels(LutKind kind);

// The number of lobe integrand evaluations (GGX and Charlie) this thread has made so far: the
// benchmarks compare rates per evaluation with the device kernels.
uint64_t lobe_evaluations_this_thread();
std::vector<double> lut_table(LutKind kind, int width, int height,
                              SheenVisibility visibility = SheenVisibility::EstevezKulla, unsigned threads = 0);

}  // namespace brdfbake::reference
