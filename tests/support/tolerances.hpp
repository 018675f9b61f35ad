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
// Double closed forms of a few tens of operations (atan2, acos, log2, pow, sqrt) on values up to
// ~10, against the same formula written another way: 10x kRounding.
inline constexpr double kRoundingFewOps = 1e-12;
// ... through a division by a small product or a bilinear weight of values up to ~1e2: 100x.
inline constexpr double kRoundingLong = 1e-11;
// ... double sums of products of O(10) terms against pi-scaled closed forms (SH polynomials).
inline constexpr double kRoundingSums = 1e-10;
// One or two operations on values of order 1: a few ulps (2.2e-16 each).
inline constexpr double kUlpsOfOne = 1e-15;
// A relative difference after two double roundings (each 2^-53 = 1.1e-16), e.g. f / s * s.
inline constexpr double kTwoRoundings = 4e-16;
// A panel breakpoint placed at 1e-6 by a few double operations: a few ulps of 1e-6 (2e-22 each).
inline constexpr double kPanelBreakpoint = 1e-20;
// Spot values quoted to six decimals (SH basis constants 0.282095, 0.488603, 1.092548): half a
// unit of the sixth decimal is 5e-7.
inline constexpr double kSixDecimals = 1e-6;
// GGX Lambda at alpha tan = 1e-6 against its small-slope form alpha^2 tan^2 / 4: the next term is
// O(alpha^2 tan^2) = 1e-12 relative, and the naive formula's cancellation would lose all digits.
inline constexpr double kSmallSlopeSeries = 1e-10;
// Lambda's one-sided difference quotients at step h either side of its seam: they differ by
// O(h |Lambda''|), Lambda'' being O(10) there (relative to the slope).
inline constexpr double kOneSidedSlopes = 1e-4;
// The test's own hemisphere quadrature (fixed Gauss-Legendre on theta, phi) of the normalisation of
// peaked distributions (alpha down to 1e-3): converged to 1e-7, bounded at 1e-6.
inline constexpr double kNdfNormalisation = 1e-6;
// The solid angle of a face's centre texel against (2 / S)^2 at S = 1000: the exact form differs by
// (1 + a^2 + b^2)^(-3/2) with a, b ~ 1e-3, 1.5e-6 relative.
inline constexpr double kSmallTexelSolidAngle = 1e-5;

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
// The accuracy report's quadrature chains (tests/host/test_report.cpp, bench sizes of 8^2 from a
// tiny source) against the brute-force reference: kEnvPrefilterRms's box-vs-bilinear difference at
// first order on the coarsest sources (measured worst: 0.0498, level 1 of the GGX chain).
inline constexpr double kEnvPrefilterReportRms = 0.05;
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
// The reference's bilinear lookup just either side of a cube edge (positions 1e-9 apart): the
// weights move by O(1e-9 S), and the two faces' edge texels agree.
inline constexpr double kEdgeContinuity = 1e-6;
// The reference's prefilter of a single lit texel against the lobe at its centre: the bilinear
// tent spreads the texel over its neighbours, a second-order change of the lobe (relative).
inline constexpr double kBilinearTent = 0.02;
// Our SH of an environment against cmgen's (tests/device/test_engine_filament.cpp): two programs'
// projections of the same input, relative to the larger of the coefficient and its channel's band
// 0 (a 1% change of the lit result). Measured worst: 0.25%.
inline constexpr double kCmgenSh = 0.01;
// Babylon's constant 0.886277 for pi Y_00 = 0.886227 puts its band 0 5.6e-5 high; its other
// constants carry 6 digits.
inline constexpr double kBabylonBand0 = 6e-5;

// --- Thin film (tests/reference/test_thin_film_reference.cpp, tests/device/test_thin_film.cpp) ---
// Closed forms evaluated by the reference in double: rounding only.
inline constexpr double kThinFilmClosedForm = 1e-12;
// The fits of Belcour & Barla are normalised by 1.0685e-7, the integral of y-bar to 4 digits, and
// their x and z integrals match it to 1e-3: the white point of the sensor is (1, 1, 1) to 2e-3
// (scaled by each row of the XYZ -> Rec. 709 matrix where it is applied).
inline constexpr double kSensorWhite = 2e-3;
// A film 20 um thick: exp(-var phase^2) of every Gaussian is below 1e-30, so only C0 remains.
inline constexpr double kThinFilmIncoherent = 1e-12;
// fp32: the phases reach pos * phase ~ 2.2e6 * 2 pi * 4320e-9 ~ 60 rad, where a float keeps
// 4e-6 rad; the series multiplies that by amplitudes below 1. Measured worst: 6e-7.
inline constexpr double kThinFilmFp32 = 1e-5;
// fp64: rounding of the same arithmetic.
inline constexpr double kThinFilmFp64 = 1e-10;

// --- Material presets (tests/host/test_material_presets.cpp) ---
// Water's dispersion: n runs 1.332-1.339 from 630 to 465 nm, F0 0.0203-0.0210 around 0.0204 (n_D).
inline constexpr double kWaterF0Spread = 7e-4;
// Hard-coded F0 tables (RTR4, Hoffman) come from other samples than our three-wavelength indices.
// Conductors (F0 0.4-1.0): the widest gap is titanium blue, 0.549 (Johnson & Christy 1974, 465 nm)
// against RTR4's 0.449; a swapped n/k or a typo moves F0 by far more.
inline constexpr double kCommonF0GapConductor = 0.11;
// Dielectrics (F0 0.02-0.18), quoted to one or two digits (0.02, 0.04, 0.05, 0.028): the widest
// gaps are skin at 465 nm (0.0337 against RTR4's 0.028) and fused silica (0.0346 against 0.04).
// An index 0.1 off moves F0 by >= 0.01 (dF0/dn = 4 (n - 1) / (n + 1)^3, 0.13 at n = 1.5).
inline constexpr double kCommonF0GapDielectric = 0.007;
// F82-tint fitted (F0 and tint) to the preset metals stays within a few hundredths of the exact
// curve (worst: chromium red, 0.023); plain Schlick misses the dark metals by up to 0.2.
inline constexpr double kF82FitMaxError = 0.025;

// --- What a file keeps of a float (tests/support/table_readback.hpp, tests/host) ---
// binary16 rounds to nearest: half an ulp, 2^-11 of the value for normal numbers ...
inline constexpr double kBinary16Rounding = 1.0 / 2048.0;
// ... and half the subnormal spacing 2^-24 below 2^-14.
inline constexpr double kBinary16Subnormal = 1.0 / 33554432.0;
// 16-bit PNG: half a step of 65535 over the stored range [0, max(1, largest)].
inline constexpr double kPng16Step = 0.5 / 65535.0;
// Radiance RGBE keeps 8 mantissa bits under an exponent shared by the pixel's three channels:
// frexp puts the largest channel in [2^(e-1), 2^e), so every channel is quantised in steps of
// 2^e / 256 <= largest / 128 (truncated: a channel reads back within one step below its value).
inline constexpr double kRgbeStepOfLargest = 1.0 / 128.0;
// Numbers printed with %.9g (CSV, .h, text keys): half a unit of the ninth significant digit is
// below 5e-10 for values below 1 ...
inline constexpr double kTextNineDigitsBelowOne = 1e-9;
// ... and below 5e-9 for values below 10.
inline constexpr double kTextNineDigits = 1e-8;
// A float image resampled at a texel centre (the equirect writer): float bilinear weights, a few
// float ulps of values of order 1.
inline constexpr double kFloatResampling = 1e-6;
// log10 of extremes stored as float (6e-8 relative, 3e-8 in log10), computed in float by the
// contact sheet's scale.
inline constexpr double kFloatLog10 = 1e-6;
// ASTC HDR through astcenc at effort 10 (its fast preset) on the synthetic chain of
// test_engines.cpp, decoded by astcenc: a channel's error is a fraction of the largest value in its
// block (endpoints and weights are quantised per block), and the chain's blocks span 0.015 .. 40 on
// the small levels. Measured worst: 0.108 of the block's largest value (4x4), 0.247 (6x6); with the
// faces stored in reverse order (face +Y is 5x brighter than the others): 3.8 to 4.1.
inline constexpr double kAstcHdr4x4OfBlock = 0.15;
inline constexpr double kAstcHdr6x6OfBlock = 0.3;

// --- Front ends (tests/host) ---
// fp32 device values through the command line's CSV against the double reference: the kernel's
// kBrdfFp32, plus the rounding of the CSV's 9 significant digits.
inline constexpr double kCliFp32 = 2e-5;
// A reference table converged to 1e-9 and stored as float32 (6e-8 relative, two roundings).
inline constexpr double kReferenceStorage = 1.2e-7;
// fp32 Fresnel tables at points where the formula is exact (cos 1: F = F0): float rounding of
// values <= 1, 6e-8.
inline constexpr double kFresnelFp32Exact = 1e-7;

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
