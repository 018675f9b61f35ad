# The table families whose code lives in its own folder (docs/ARCHITECTURE.md, "How to add a table
# family"): family F has its kernel kernels/F.cl, its folder host/src/families/F/ (its sources listed
# in the folder's sources.cmake) and its reference file host/reference/src/F.cpp. Included by
# host/CMakeLists.txt (the library and the embedded kernels) and host/reference/CMakeLists.txt.
set(BRDFBAKE_FAMILIES
  dfg_lut
  fresnel
  thin_film
  prefilter
  irradiance
  brdf_eval
  preview
)
