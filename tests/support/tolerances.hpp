// Named tolerances of the test suite, each with the reason for its size.
#pragma once

namespace brdfbake::test {

// The reference integrals are stated converged to 1e-6 absolute; comparisons between two
// reference evaluations by different routes (identities) allow twice that.
inline constexpr double kReferenceConverged = 2e-6;

// Closed forms against double arithmetic of a few operations, or quadratures exact by construction.
inline constexpr double kRounding = 1e-13;
// Reference against its doubled resolution (2x order, 2x refinement): 10x inside the 1e-6 contract.
inline constexpr double kSelfConvergence = 1e-7;
// Reference against closed forms or independent quadratures converged to 1e-11: all but rounding.
inline constexpr double kAnalytic = 1e-9;
// Test-side quadratures of the identities (D normalisation, visible normals): smooth integrands.
inline constexpr double kIdentityQuadrature = 1e-9;
// Brute-force l-space quadrature must itself be converged this well before it may judge.
inline constexpr double kBruteForceConverged = 1e-10;
// GGX at roughness 1e-3 against the mirror limit: its deviation is O(alpha tan^2) = O(1e-6) at
// n.v = 1e-3 and far smaller above; this bound holds down to n.v = 1e-3.
inline constexpr double kMirrorLimit = 2e-6;
// n.v = 0 against the n.v -> 0 limit: the reference evaluates it at n.v = 1e-16, and the integrals
// are linear in n.v there with slopes up to ~3e7 (alpha floor), so 3e-9 plus extrapolation rounding.
inline constexpr double kGrazingLimit = 1e-8;

// --- Device kernels against the reference (tests/device) ---
// The default sample count of every DFG table is calibrated to keep the 128x128 table within 1e-4
// max abs of the reference (docs/BENCHMARKS.md); the tests hold each kernel to that promise.
inline constexpr double kLutDefaultBound = 1e-4;
// fp32 storage and arithmetic: values of order 1 summed over a few hundred nodes lose ~1e-6;
// 4e-6 leaves room for the longest sums (Charlie's values reach ~12 at grazing, sheen roughness 0).
inline constexpr double kLutFp32Rounding = 4e-6;
// fp64 quadrature at 8192 evaluations converges below 1e-7 in our sweeps; the reference's own
// 1e-6 contract dominates.
inline constexpr double kLutQuadratureFp64 = 2e-6;

// The mirror limit (tests/identities/dfg_identities.hpp) on the device at its default sample counts,
// roughness 0 and 1e-3: the limit's own deviation at 1e-3 (kMirrorLimit) plus the quadrature and
// float storage, the bound the device's mirror test has always had. Measured worst 6.9e-7 (fp32),
// 5.7e-7 (fp64).
inline constexpr double kLutMirrorDevice = 10 * kLutFp32Rounding;

// Charlie in fp32 at n.v <= 1e-6 with sheen roughness <= 1e-3, where the albedo is 260 to 1600
// and the integrand lives where cos(theta_h) ~ n.v ~ 1e-7: fp32 quadrature plateaus at ~1e-3
// relative there (fp64 agrees with the reference to 1e-6). Measured worst: 9.4e-4.
inline constexpr double kCharlieDegenerateFp32 = 2e-3;

// --- Fresnel identities on the reference (tests/identities/fresnel_identities.hpp) ---
// Two routes to the same closed form in double (different operation order, csqrt): a few ulps of
// values <= 1, ulp 2.2e-16.
inline constexpr double kFresnelReferenceRounding = 1e-15;
// F has a square-root branch point at the critical angle: a step of 1e-9 in cos moves it by
// O(sqrt(1e-9)), 3.4e-4 for eta = 1/1.5 (continuous, but not Lipschitz). A jump would be O(1).
inline constexpr double kFresnelCriticalAngleStep = 1e-3;

// --- Fresnel kernels against the reference (tests/device/test_fresnel.cpp) ---
// fp32 tables: cos_theta and the parameters rounded to float, a few ulps of arithmetic on values
// <= 1, then float storage. Measured worst: 3.0e-7 over every preset; 6.0e-7 (ten float ulps
// below 1) for the extreme conductor n = 10, k = 100, whose products of four large terms round most.
inline constexpr double kFresnelFp32 = 1e-6;
// fp64 tables: both sides are rounded to float storage, so one float ulp below 1 (2^-24) remains.
inline constexpr double kFresnelFp64 = 6e-8;
// fp32 internal reflection: F = 1 - C sqrt(d) at a distance d past the critical angle, so a
// float rounding delta of cos_theta (or eta) moves F by C delta / (2 sqrt(d)). Measured worst: 1.9e-5
// (eta = 1/1.5, the cell centre 1.4e-4 from the critical angle).
inline constexpr double kFresnelCriticalAngleFp32 = 1e-4;
// fp32 near-index-matched dielectrics (|eta - 1| < 1e-2): float(eta) - 1 carries a relative error
// up to 6e-8 / |eta - 1| (1.7e-5 at eta = 1.0001), which shifts F's steep rise near grazing.
// Measured worst (eta = 1.0001): 3.0e-5.
inline constexpr double kFresnelIndexMatchedFp32 = 1e-4;
// cos_theta = 0 gives 1 up to the last bits of a float (contracted multiply-adds): two ulps below 1.
inline constexpr double kFresnelGrazingOne = 1.2e-7;
// The Schlick spot values are quoted to 5 decimals.
inline constexpr double kFresnelSpotValue = 5e-6;

// --- Bulk BRDF kernels against the reference (tests/device/test_brdf_eval.cpp) ---
// Error measure: |got - want| / max(1, |want|), the reference fed the directions the device saw.
// fp32: a few float roundings of each term; measured worst 3.5e-6 (gltf sheen, grazing corners).
inline constexpr double kBrdfFp32 = 1e-5;
// fp32 tables (MERL, grid, slice) generate their directions from angles on the device: the
// direction moves by ~1e-7 rad, which lobes at least 0.09 wide turn into < 1e-5 relative ...
inline constexpr double kBrdfTableFp32 = 2e-5;
// ... and near the horizon a cosine is a difference of O(1) terms, ~1e-7 off absolutely, which the
// 1/n.l, 1/n.v of the visibilities turn into ~1e-7 / cos relative (measured 1.7e-8 / cos).
inline constexpr double kBrdfTableDirection = 1e-7;
// fp64: rounding, and the sheen albedo E(mu): the kernels' cubic pieces (built by the engine from its
// own quadrature, host/src/families/brdf_eval/sheen_albedo.cpp) against the reference's Chebyshev series (from
// charlie_albedo): the pieces are within 1e-12 of the true E except on the upper panel next to the
// Lambda fit's seam at mu = 1/2 (1.05e-9 at sheen roughness 0.3, as the pieces of the reference's own
// series were), the series within 1.8e-10; measured worst 7.6e-10 (gltf, random inputs). Worst
// otherwise Phong at n = 1e6 (2.2e-10: the exponent amplifies the last bits of ln cos).
inline constexpr double kBrdfFp64 = 1e-9;
// The device albedo's fixed quadrature against the reference's adaptive one (1e-7), in float
// table storage: measured worst 5.3e-6 (disney) over random and corner materials of every model ...
inline constexpr double kBrdfAlbedoQuadrature = 2e-5;
// ... but for Phong, whose max(0, r.v)^n has a kink (n = 1: 4.1e-5) or a step (n = 0: 2.4e-4) where
// r.v changes sign inside the hemisphere, which a fixed rule resolves only slowly.
inline constexpr double kPhongAlbedoKink = 5e-4;
// Albedo bounds of the models that do not conserve energy (docs/CONVENTIONS.md, "Energy"),
// measured by the reference's adaptive quadrature: normalised Blinn-Phong (max 1.0748 at n = 10,
// normal incidence); Disney's diffuse with a white base (max 1.5655 at roughness 1, grazing).
inline constexpr double kBlinnPhongAlbedoBound = 1.076;
inline constexpr double kDisneyDiffuseAlbedoBound = 1.567;

// --- Environment maps (tests/reference/test_envmap_reference.cpp, tests/device/test_prefilter.cpp,
// tests/device/test_irradiance.cpp) ---
// The reference's sub-cell sums against the exact lobe normalisation and against doubled sub-cells:
// the midpoint rule on the sphere with q chosen to resolve the lobe (measured worst 2e-4).
inline constexpr double kEnvReferenceSubCells = 1e-3;
// SH of a constant cube from sub-cell samples: the l = 4 cubic harmonic is integrated with an
// O(1/(S q)^2) error (measured 4e-4 of L_00 at S q = 32, ~2.5e-5 at the default S q >= 128); every
// other coefficient vanishes by symmetry.
inline constexpr double kEnvShDiscretisation = 1e-3;
// Direct cosine convolution against the 9-coefficient SH route for an environment of degree 2: the
// bilinear interpolation of texel samples is not exactly quadratic (measured 1e-3 at S = 16).
inline constexpr double kEnvIrradianceRoutes = 5e-3;
// The reference's cosine convolution of a constant environment at its default S q >= 128: the
// kink at the horizon costs O(1/(S q)^2) (measured 2.0e-5).
inline constexpr double kEnvReferenceCosine = 5e-5;
// White furnace: a constant environment through every kernel, fp32 sums of ~1e4 terms.
inline constexpr double kEnvFurnace = 1e-5;
// Device prefilter against the brute-force reference on 16^2 - 32^2 cubes: the aim of 1%
// RMS relative error per level (measured worst 0.63%), and a bound on the worst texel: on sources
// this coarse the pyramid's box texels and the reference's bilinear interpolation differ at first
// order where a softbox edge meets Charlie's ring (measured worst 5.8%, GGX 1.8%).
inline constexpr double kEnvPrefilterRms = 0.01;
inline constexpr double kEnvPrefilterMax = 0.08;
// fp32 against fp64 kernels on the same source: sums of ~1e4 terms in fp32 (measured 2e-6).
inline constexpr double kEnvFp32VsFp64 = 1e-4;
// The sampling estimator (importance sampling with filtered importance sampling) at 4096 samples
// per texel on 32^2 cubes: its mip blur is a bias that falls like 1/N (docs/BENCHMARKS.md).
inline constexpr double kEnvSamplingRms = 0.02;
inline constexpr double kEnvSamplingMax = 0.10;
// The host SH projection is exact for an equirect's pixels and a cube's texel centres: against an
// independent 16 x 16-node Gauss-Legendre quadrature per pixel (converged to ~1e-14) and the
// reference's texel-centre sum, only double rounding remains (measured 6e-16 of the largest coefficient).
inline constexpr double kShExactProjection = 1e-12;
// The engine's SH of a cube (texel centres, exact solid angles) against the reference's sub-cell
// projection of the same cube: the two quadratures differ by O(1 / S^2) of L00.
inline constexpr double kShTexelCentres = 2e-3;
// Device irradiance cube against the reference's brute force on a 64^2 source: the device sums
// texels as boxes, the reference interpolates them bilinearly (a tent twice as wide), which differs
// by O(texel size) only where a sun of 5e4 sits on a normal's horizon (measured worst 0.87%, RMS
// 0.1%); elsewhere both agree to ~1e-4.
inline constexpr double kEnvIrradianceDevice = 1e-2;
inline constexpr double kEnvIrradianceDeviceRms = 2e-3;
// The reference backend's equirect-to-cube conversion (q x q sub-cells per texel, q >= 4 per equirect
// pixel) against the device's (k x k samples, fp32): both estimate each texel's mean of the same
// bilinear equirect; on a smooth one their sampling errors are O(texel^2) of its curvature, plus
// fp32 (measured on 32^2 from 256 x 128: RMS 8e-6, worst 4.3e-5).
inline constexpr double kEnvConversionRoutesRms = 5e-5;
inline constexpr double kEnvConversionRoutesMax = 2e-4;
// --- BRDF reference (tests/reference/test_brdf_reference.cpp) ---
// f(wi, wo) against f(wo, wi): the same terms in another order of operations (l.h vs v.h, the
// normalisation of each vector).
inline constexpr double kBrdfReciprocity = 1e-12;
// The reference albedo (adaptive, 1e-7 absolute per panel budget) against independent integrals
// converged to 1e-6 (the DFG reference's contract) or closed forms.
inline constexpr double kBrdfAlbedoReference = 2e-6;
// The sheen albedo's Chebyshev series against charlie_albedo at twice the order and refinement:
// measured 7e-10; the series' nodes carry charlie_albedo's own 1e-9.
inline constexpr double kSheenAlbedoSeries = 1e-8;
// The engine's own quadrature of the same integral (over l, adaptive, host/src/families/brdf_eval/sheen_albedo.cpp)
// against charlie_albedo at twice the order and refinement: two converged quadratures by different
// routes, relative above 1 (measured 5e-13 at the series' nodes).
inline constexpr double kSheenAlbedoEngine = 1e-11;

}  // namespace brdfbake::test
