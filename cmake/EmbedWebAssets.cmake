# Embeds the web page's files (host/server/web/) into a generated C++ file in the build tree, as byte
# arrays, so that `brdfbake serve` serves its page with no file beside the binary and no network.
#
#   brdfbake_embed_web_assets(OUTPUT <file.cpp> BASE_DIR <dir> FILES <relative paths>...)
#
# The generated file defines brdfbake::server::detail::web_assets(), a list of {path, bytes, size}.
# Each file is a dependency, so editing one regenerates and rebuilds.
set(BRDFBAKE_EMBED_WEB_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/EmbedWebAssetsScript.cmake)

function(brdfbake_embed_web_assets)
  cmake_parse_arguments(ARG "" "OUTPUT;BASE_DIR" "FILES" ${ARGN})
  set(deps)
  foreach(f IN LISTS ARG_FILES)
    list(APPEND deps ${ARG_BASE_DIR}/${f})
  endforeach()
  string(REPLACE ";" "|" files_arg "${ARG_FILES}")
  add_custom_command(
    OUTPUT ${ARG_OUTPUT}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${ARG_OUTPUT} -DBASE_DIR=${ARG_BASE_DIR}
            "-DFILES=${files_arg}" -P ${BRDFBAKE_EMBED_WEB_SCRIPT}
    DEPENDS ${deps} ${BRDFBAKE_EMBED_WEB_SCRIPT}
    COMMENT "Embedding the web page into ${ARG_OUTPUT}"
    VERBATIM)
endfunction()
