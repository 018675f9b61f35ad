# The preview family's sources (host/families.cmake).
set(BRDFBAKE_FAMILY_SOURCES
  family.cpp
  model.cpp
  shading.cpp
  tree.cpp
  kernel.cpp
  opencl.cpp
  reference.cpp
  bake_files.cpp
  splitsum.cpp
  ideal.cpp
  iridescence.cpp
  render.cpp
  output.cpp
  bake_preview.cpp
)
