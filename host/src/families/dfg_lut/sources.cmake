# The DFG family's sources (host/families.cmake).
set(BRDFBAKE_FAMILY_SOURCES
  family.cpp
  model.cpp
  calibration.cpp
  kernel.cpp
  opencl.cpp
  reference.cpp
)
