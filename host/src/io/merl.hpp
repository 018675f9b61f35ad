// Internal: the MERL BRDF layout (Matusik, Pfister, Brand & McMillan 2003, "A Data-Driven
// Reflectance Model"), as MERL's reader (BRDFRead.cpp: read_brdf, lookup_brdf_val) defines it.
//
// A bin (i, j, k) indexes theta_h, theta_d and phi_d of Rusinkiewicz's half/difference angles:
//   i = floor(sqrt(theta_h / (pi/2)) * 90)   (non-linear: fine near the specular peak)
//   j = floor(theta_d / (pi/2) * 90)
//   k = floor(phi_d / pi * 180), phi_d folded into [0, pi) by reciprocity (phi_d < 0 -> phi_d + pi)
// and the file stores bin (i, j, k) of channel c at ((c * 90 + i) * 90 + j) * 180 + k, as doubles that
// the reader multiplies by 1/1500, 1.15/1500 and 1.66/1500 (red, green, blue). brdfbake writes bin
// (i, j, k) at its centre on these axes: theta_h = ((i + 0.5)/90)^2 pi/2, theta_d = (j + 0.5)/90 pi/2,
// phi_d = (k + 0.5)/180 pi, phi_h = 0.
#pragma once

#include <cstddef>

#include "brdfbake/brdf.hpp"

namespace brdfbake::io {

// What MERL's reader multiplies each channel by.
inline constexpr double kMerlScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

// The half/difference angles of a bin's centre.
struct MerlAngles {
  double theta_h, theta_d, phi_d;
};
MerlAngles merl_bin_centre(int i, int j, int k);

// wi and wo of half/difference angles with phi_h = 0 (MERL's half_diff_coords_to_std_coords):
// wi = R_y(theta_h) d, d = (sin td cos pd, sin td sin pd, cos td); wo = 2 (wi.h) h - wi.
void half_diff_to_directions(double theta_h, double theta_d, double phi_d, Vec3& wi, Vec3& wo);

// The flat index (in one channel) of the bin a direction pair falls in, as lookup_brdf_val
// computes it from std_coords_to_half_diff_coords.
std::size_t merl_index(const Vec3& wi, const Vec3& wo);

}  // namespace brdfbake::io

namespace brdfbake {
// A MERL binary held in memory (read_merl without the file and its sidecar): checks the header's
// dimensions and the size before allocating; throws Error naming `origin`.
MerlTable decode_merl(const std::string& bytes, const std::string& origin);
}  // namespace brdfbake
