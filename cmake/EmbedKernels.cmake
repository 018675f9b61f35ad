# Embeds OpenCL C sources (.cl and .clh) into a generated C++ file in the build tree.
#
#   brdfbake_embed_kernels(OUTPUT <file.cpp> BASE_DIR <dir> FILES <relative paths>...)
#
# The generated file defines brdfbake::detail::embedded_kernel_sources(), a list of
# {relative path, text}. Each file is a dependency, so editing a .cl file regenerates and rebuilds.
set(BRDFBAKE_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/EmbedKernelsScript.cmake)

function(brdfbake_embed_kernels)
  cmake_parse_arguments(ARG "" "OUTPUT;BASE_DIR" "FILES" ${ARGN})
  set(deps)
  foreach(f IN LISTS ARG_FILES)
    list(APPEND deps ${ARG_BASE_DIR}/${f})
  endforeach()
  string(REPLACE ";" "|" files_arg "${ARG_FILES}")
  add_custom_command(
    OUTPUT ${ARG_OUTPUT}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${ARG_OUTPUT} -DBASE_DIR=${ARG_BASE_DIR}
            "-DFILES=${files_arg}" -P ${BRDFBAKE_EMBED_SCRIPT}
    DEPENDS ${deps} ${BRDFBAKE_EMBED_SCRIPT}
    COMMENT "Embedding OpenCL kernels into ${ARG_OUTPUT}"
    VERBATIM)
endfunction()
