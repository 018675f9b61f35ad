// Internal: the preview family's kernel, the calculation a backend runs: the reference render's
// integrals for a list of pixels (normals) under an equirect environment. Its implementations:
// opencl.cpp (kernels/preview.cl, the quadtree walk) and reference.cpp (the scalar double
// reference's brute force, host/reference/src/preview.cpp); family.cpp registers both.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/math/types.hpp"

namespace brdfbake::detail {

// One pixel: its unit normal, alpha, and the exact directional albedos of the GGX lobe at its n.v
// (A = int D V n.l, B = int D V Fc n.l: the walk's normalisation; unused by the brute force).
struct ReferencePixel {
  float n[3] = {0.0f, 0.0f, 1.0f};
  float alpha = 0.0f;
  float albedo = 1.0f;
  float bias = 0.0f;
  // The Charlie sheen lobe (KHR_materials_sheen: D_Charlie, Estevez & Kulla's visibility) instead of
  // GGX; then albedo is its exact albedo E(n.v) and S2 is 0.
  bool sheen = false;
  // The GGX lobe times the thin-film Fresnel (KHR_materials_iridescence: the film's thickness in nm,
  // its index, the base's F0 under it, seen from air) instead of Schlick's two integrals: S1 is
  // int D V F_irid,c(v.h) n.l L_c per channel, S2 is 0; albedo and bias are the GGX lobe's A and 0 (the
  // walk's normalisation). The program is built with PREVIEW_IRIDESCENCE only when a pixel has one.
  bool film = false;
  float film_thickness = 0.0f;
  float film_ior = 1.0f;
  float film_base_f0[3] = {0.0f, 0.0f, 0.0f};
};

struct ReferenceTask {
  const EnvImage* environment = nullptr;  // an equirect
  Vec3 view{0.0, 0.0, 1.0};               // unit, from the surface towards the viewer
  std::vector<ReferencePixel> pixels;
  // Rendered again at twice the refinement (the reference's bound is measured on them).
  std::vector<ReferencePixel> bound_pixels;
  double refinement = 4.0;      // the walk's (kernels/preview.cl)
  double radiance_scale = 1.0;  // a typical pixel's irradiance (pi x median luminance)
  Precision precision = Precision::Fp32;
};

struct ReferenceSums {
  std::vector<double> values;        // 9 a pixel: S1 (rgb), S2 (rgb), Irr (rgb)
  std::vector<double> bound_values;  // the same for bound_pixels, at twice the refinement
  std::vector<int> cells;            // cells visited a pixel (the walk; 0 for the brute force)
  size_t overflows = 0;              // pixels whose walk overflowed its stack (summed coarser there)
  double device_seconds = 0.0, wall_seconds = 0.0;
  double bound_device_seconds = 0.0, bound_wall_seconds = 0.0;
  std::string method;  // how the integrals were computed
};

class PreviewKernel : public BackendKernel {
 public:
  static constexpr const char* kName = "preview";
  virtual ReferenceSums reference(const ReferenceTask& task, const std::function<void(double)>& progress) = 0;
};

std::unique_ptr<PreviewKernel> make_opencl_preview(Device& device);
std::unique_ptr<PreviewKernel> make_reference_preview();

// The backend's implementation, under its call lock.
ReferenceSums run_preview_reference(Backend& backend, const ReferenceTask& task,
                                    const std::function<void(double)>& progress = {});

// The walk's thresholds at a refinement (kernels/preview.cl, PreviewRules): straddling cells larger
// than horizon_size, or whose luminance(L Omega) x rho exceeds horizon_energy, and every cell larger
// than max_size, are refined. All halve (the energy falls 8-fold) when the refinement doubles.
struct PreviewRulesValues {
  double horizon_size, horizon_energy, max_size;
};
PreviewRulesValues preview_rules(double refinement, double radiance_scale);

}  // namespace brdfbake::detail
