# The BRDF evaluation engine's sources (host/families.cmake): the eval and tabulate families.
set(BRDFBAKE_FAMILY_SOURCES
  eval_family.cpp
  tabulate_family.cpp
  pairs.cpp
  names.cpp
  material.cpp
  sheen_albedo.cpp
  evaluator.cpp
  tabulate.cpp
  kernel.cpp
  opencl.cpp
  reference.cpp
)
