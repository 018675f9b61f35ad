# The Fresnel family's sources (host/families.cmake).
set(BRDFBAKE_FAMILY_SOURCES
  family.cpp
  names.cpp
  resolve.cpp
  conductor.cpp
  metadata.cpp
  errors.cpp
  compare.cpp
  kernel.cpp
  opencl.cpp
  reference.cpp
)
