# `cmake --install`: the packager, the dearchiver and the OpenGL runtime with their public headers, a
# CMake package (find_package(statepack CONFIG): statepack::dearchiver, statepack::gl,
# statepack::statepack, statepack::bootstrap(_gl) and statepack_add_archive) and a pkg-config file for the library. Every path is relative to the prefix,
# so `cmake --install build --prefix DIR` works for any DIR.
include(CMakePackageConfigHelpers)
set(statepack_config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/statepack)

set(statepack_installed_targets statepack_dearchiver)
if(STATEPACK_BUILD_GL)
  list(APPEND statepack_installed_targets statepack_gl)
endif()
if(STATEPACK_BUILD_PACKAGER)
  # The packager, and the bootstrap (device, GL context, host tools) that the samples build against.
  list(APPEND statepack_installed_targets statepack statepack_bootstrap_vulkan)
  if(STATEPACK_BUILD_GL)
    list(APPEND statepack_installed_targets statepack_bootstrap_gl)
  endif()
  install(DIRECTORY dearchiver/bootstrap/include/statepack DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
install(TARGETS ${statepack_installed_targets} EXPORT statepackTargets
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY dearchiver/include/statepack DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT statepackTargets NAMESPACE statepack:: DESTINATION ${statepack_config_dir})

# The config finds what the exported dearchiver links: Vulkan always, and for a static library also its
# private dependencies, which end up in the application's link.
if(STATEPACK_SHARED)
  set(STATEPACK_STATIC_DEARCHIVER OFF)
else()
  set(STATEPACK_STATIC_DEARCHIVER ON)
endif()
configure_package_config_file(cmake/statepackConfig.cmake.in ${PROJECT_BINARY_DIR}/statepackConfig.cmake
  INSTALL_DESTINATION ${statepack_config_dir} NO_SET_AND_CHECK_MACRO)
# 0.x: a minor release may change the API, so only the same major.minor satisfies a request.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/statepackConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/statepackConfig.cmake ${PROJECT_BINARY_DIR}/statepackConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/packager/StatepackAddArchive.cmake
        DESTINATION ${statepack_config_dir})

# pkg-config: the prefix is found from the .pc file's own place (${pcfiledir}), so it too is relocatable.
# A static library's users need libxxhash on their link line even without `pkg-config --static`.
file(RELATIVE_PATH statepack_pc_to_prefix ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" statepack_pc_to_prefix "${statepack_pc_to_prefix}")
# Vulkan only for its headers (--cflags): the library opens the loader at run time or uses the
# application's dispatch, so it puts no -lvulkan on anyone's link line.
if(STATEPACK_SHARED)
  set(statepack_pc_requires "")
  set(statepack_pc_requires_private "vulkan libxxhash")
else()
  set(statepack_pc_requires "libxxhash")
  set(statepack_pc_requires_private "vulkan")
endif()
configure_file(cmake/statepack_dearchiver.pc.in ${PROJECT_BINARY_DIR}/statepack_dearchiver.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/statepack_dearchiver.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(STATEPACK_BUILD_GL)
  # The OpenGL runtime: on top of the dearchiver's (Archive) and libepoxy's.
  configure_file(cmake/statepack_gl.pc.in ${PROJECT_BINARY_DIR}/statepack_gl.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/statepack_gl.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()
