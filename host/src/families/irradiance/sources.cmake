# The irradiance family's sources (host/families.cmake).
set(BRDFBAKE_FAMILY_SOURCES
  family.cpp
  model.cpp
  sh.cpp
  sh_projection.cpp
  sh_window.cpp
  sh_error.cpp
  kernel.cpp
  opencl.cpp
  reference.cpp
)
