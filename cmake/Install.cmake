# cmake --install: the command-line tool, the library with its public headers, a CMake package
# (find_package(brdfbake) -> brdfbake::brdfbake) and a pkg-config file (pkg-config brdfbake).
include(CMakePackageConfigHelpers)

set(BRDFBAKE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/brdfbake)

# The library is static: the maths its headers use and the oracle it links privately are installed
# beside it.
install(TARGETS brdfbake_lib brdfbake_math brdfbake_reference
        EXPORT brdfbakeTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/host/include/brdfbake DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")
install(FILES ${PROJECT_BINARY_DIR}/include/brdfbake/version.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/brdfbake)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/host/math/include/brdfbake DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")
if(TARGET brdfbake)
  install(TARGETS brdfbake RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
# The lazily loaded OpenImageIO module (formats beyond EXR, PNG and HDR), where the library looks for
# it: PREFIX/lib/brdfbake/ beside ../bin.
install(TARGETS brdfbake_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/brdfbake)

install(EXPORT brdfbakeTargets NAMESPACE brdfbake:: DESTINATION ${BRDFBAKE_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/brdfbakeConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/brdfbakeConfig.cmake
                              INSTALL_DESTINATION ${BRDFBAKE_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/brdfbakeConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/brdfbakeConfig.cmake ${PROJECT_BINARY_DIR}/brdfbakeConfigVersion.cmake
        DESTINATION ${BRDFBAKE_CMAKE_DIR})

# pkg-config: the static library and what it needs at link time.
set(BRDFBAKE_PC_LIBS_PRIVATE "-lbrdfbake_reference -lbrdfbake_math -lastcenc")
set(BRDFBAKE_PC_REQUIRES_PRIVATE "OpenCL OpenEXR libpng")
configure_file(${PROJECT_SOURCE_DIR}/cmake/brdfbake.pc.in ${PROJECT_BINARY_DIR}/brdfbake.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/brdfbake.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
