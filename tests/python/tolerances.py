"""Named tolerances of the Python tests, each with its reason (the C++ suite's are in
tests/support/tolerances.hpp; these reuse its measurements where the same kernels are checked)."""

# Fresnel tables in fp32 against closed-form spot values: float rounding of the exact formula
# (tests/support/tolerances.hpp kFresnelFp32).
FRESNEL_FP32 = 1e-6

# A constant environment through the SH projection and the prefilter in fp32: sums of ~1e4 terms
# (kEnvFurnace).
ENV_FURNACE = 1e-5

# The prefilter's hierarchical quadrature of a constant environment: the lobe normalisation is
# computed from the same quadrature weights, so only fp32 summation remains; measured 3e-7 here,
# bounded like the furnace.
PREFILTER_FURNACE = 1e-5

# Bulk BRDF kernels in fp32 against the scalar double reference, |got - want| / max(1, |want|)
# (kBrdfFp32, measured worst 3.5e-6).
BRDF_FP32 = 1e-5

# The device albedo's fixed quadrature in float table storage against a closed form
# (tests/support/tolerances.hpp kBrdfAlbedoQuadrature, measured worst 5.3e-6).
BRDF_ALBEDO = 2e-5

# MERL binaries store f divided by the channel scale in double: reading back multiplies by it, which
# can move the last bit of a double; the float32 array rounds that (one float32 ulp, 6e-8 relative).
MERL_READBACK = 2e-7
