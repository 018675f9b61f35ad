# Sanitizer and fuzzing builds (docs/RELIABILITY.md, "Sanitizers and fuzzing"); the presets asan and
# fuzz in CMakePresets.json set these options.
#
#   BRDFBAKE_SANITIZE="address,undefined"  every target built with ASan and UBSan; UBSan findings
#                                           abort (-fno-sanitize-recover), so a finding fails a test
#   BRDFBAKE_FUZZ=ON                        clang only: the libFuzzer harnesses of fuzz/, with the
#                                           library instrumented for coverage (and ASan + UBSan)
#
# Without BRDFBAKE_FUZZ the harnesses are still built, linked with a small driver that replays
# their seed corpora (fuzz/replay_main.cpp), so every build runs the corpora as tests.
set(BRDFBAKE_SANITIZE "" CACHE STRING "Sanitizers for every target, e.g. address,undefined (empty: none)")
option(BRDFBAKE_FUZZ "Build the libFuzzer harnesses (clang)" OFF)

if(BRDFBAKE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "BRDFBAKE_FUZZ needs clang (libFuzzer); configure with the fuzz preset")
  endif()
  if(BRDFBAKE_SANITIZE STREQUAL "")
    set(BRDFBAKE_SANITIZE "address,undefined" CACHE STRING "" FORCE)
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

if(NOT BRDFBAKE_SANITIZE STREQUAL "")
  add_compile_options(-fsanitize=${BRDFBAKE_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${BRDFBAKE_SANITIZE})
  # The one switch for code that behaves differently under AddressSanitizer (the CLI ends normally
  # so that LeakSanitizer runs, the device opens on the calling thread, ulimit rows skip).
  if(BRDFBAKE_SANITIZE MATCHES "address")
    add_compile_definitions(BRDFBAKE_ASAN=1)
  endif()
endif()
