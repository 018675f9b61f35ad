# The thin-film family's sources (host/families.cmake).
set(BRDFBAKE_FAMILY_SOURCES
  family.cpp
  model.cpp
  kernel.cpp
  opencl.cpp
  reference.cpp
)
