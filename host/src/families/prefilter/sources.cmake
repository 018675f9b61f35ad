# The prefilter family's sources (host/families.cmake).
set(BRDFBAKE_FAMILY_SOURCES
  family.cpp
  schedule.cpp
  spec.cpp
  lobes.cpp
  samples.cpp
  bright.cpp
  pyramid.cpp
  chain.cpp
  metadata.cpp
  bound.cpp
  bound_device.cpp
  kernel.cpp
  opencl.cpp
  reference.cpp
)
