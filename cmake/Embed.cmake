# Embeds files into a generated C++ file in the build tree, so that the binary needs no file beside
# it: the OpenCL sources (kernels/) and the web page (host/server/web/).
#
#   brdfbake_embed(OUTPUT <file.cpp> BASE_DIR <dir> STYLE KERNELS|WEB FILES <relative paths>...)
#
# STYLE KERNELS defines brdfbake::detail::embedded_kernel_sources(), a list of {relative path, text}
# (raw string literals); STYLE WEB defines brdfbake::server::detail::web_assets(), a list of {path,
# bytes, size} (byte arrays: any content, no escaping to get wrong). Each file is a dependency, so
# editing one regenerates and rebuilds. The generator is cmake/EmbedScript.cmake.
set(BRDFBAKE_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/EmbedScript.cmake)

function(brdfbake_embed)
  cmake_parse_arguments(ARG "" "OUTPUT;BASE_DIR;STYLE" "FILES" ${ARGN})
  if(NOT ARG_STYLE STREQUAL "KERNELS" AND NOT ARG_STYLE STREQUAL "WEB")
    message(FATAL_ERROR "brdfbake_embed: STYLE must be KERNELS or WEB (got '${ARG_STYLE}')")
  endif()
  set(deps)
  foreach(f IN LISTS ARG_FILES)
    list(APPEND deps ${ARG_BASE_DIR}/${f})
  endforeach()
  string(REPLACE ";" "|" files_arg "${ARG_FILES}")
  add_custom_command(
    OUTPUT ${ARG_OUTPUT}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${ARG_OUTPUT} -DBASE_DIR=${ARG_BASE_DIR} -DSTYLE=${ARG_STYLE}
            "-DFILES=${files_arg}" -P ${BRDFBAKE_EMBED_SCRIPT}
    DEPENDS ${deps} ${BRDFBAKE_EMBED_SCRIPT}
    COMMENT "Embedding ${ARG_BASE_DIR} into ${ARG_OUTPUT}"
    VERBATIM)
endfunction()
