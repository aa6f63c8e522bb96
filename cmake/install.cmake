# Install rules, the CMake package and the Debian package of the aovar tool (issue 21).
#
#   <prefix>/bin/aovar                              the tool
#   <prefix>/share/aovar/shader_src/                the default manifest, its templates and calibration
#   <prefix>/lib/cmake/aovar/aovarConfig.cmake      find_package(aovar CONFIG): aovar::aovar (an imported
#                             aovarConfigVersion.cmake  executable), aovar_add_shader_variants() and
#                             aovarTargets.cmake        AOVAR_DEFAULT_MANIFEST
#                             AOVarShaders.cmake
#
# `cpack -G DEB` in the build folder makes the .deb (its dependencies from dpkg-shlibdeps, plus the drivers
# aovar loads at run time). A parent project that includes aovar with FetchContent gets none of this
# unless it asks (AOVAR_INSTALL).
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

option(AOVAR_INSTALL "Generate aovar's install rules and package (default: only when it is the top-level project)"
       ${PROJECT_IS_TOP_LEVEL})
if(NOT AOVAR_INSTALL)
  return()
endif()

set(AOVAR_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/aovar" CACHE STRING "where aovarConfig.cmake goes")
set(AOVAR_INSTALL_DATADIR "${CMAKE_INSTALL_DATADIR}/aovar")

install(TARGETS aovar EXPORT aovarTargets RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The GL compilers' runner (analyze --gpu on NVIDIA and Intel chips), where aovar looks beside itself
# (gpu/gl/compiler.cpp). The arm64 runner (Adreno, Mali) is not packaged: dpkg-shlibdeps cannot read a foreign
# binary; an installed aovar finds it through $AOVAR_GL_RUNNER_DIR (docs/gpu-cost.md).
if(TARGET aovar-gl-stats)
  install(PROGRAMS ${PROJECT_BINARY_DIR}/aovar-gl-stats DESTINATION ${CMAKE_INSTALL_LIBEXECDIR}/aovar)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/shader_src DESTINATION ${AOVAR_INSTALL_DATADIR})
install(EXPORT aovarTargets NAMESPACE aovar:: DESTINATION ${AOVAR_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/aovarConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/aovarConfig.cmake
                              INSTALL_DESTINATION ${AOVAR_INSTALL_CMAKEDIR}
                              PATH_VARS AOVAR_INSTALL_DATADIR)
# 0.x: a minor release may change the manifest or the generated API, so only the same minor version matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/aovarConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/aovarConfig.cmake ${PROJECT_BINARY_DIR}/aovarConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/AOVarShaders.cmake
        DESTINATION ${AOVAR_INSTALL_CMAKEDIR})

# The Debian package. dpkg-shlibdeps declares the libraries the tool links (glslang is static; Embree, TBB,
# OSMesa, the Vulkan loader, NLopt, ...); the Vulkan drivers and EGL (the gles backend) are loaded at run time, so they are
# named by hand.
set(CPACK_PACKAGE_NAME aovar)
set(CPACK_PACKAGE_VENDOR "aovar")
set(CPACK_PACKAGE_CONTACT "aovar maintainers <aovar@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "SSAO shader variant generator, validator and cost-table toolchain")
set(CPACK_PACKAGE_INSTALL_DIRECTORY aovar)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(AOVAR_WITH_RENDER)
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "mesa-vulkan-drivers, libegl1, libegl-mesa0, libgles2")
endif()
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "cmake (>= 3.25), ninja-build")
set(CPACK_STRIP_FILES ON)
include(CPack)
