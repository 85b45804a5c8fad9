# `cpack -G DEB` in the build directory: one Debian package with everything `cmake --install` puts in
# place (the packager, the library and its headers, the CMake and pkg-config files), under /usr, where
# find_package and pkg-config look without being told.
set(CPACK_PACKAGE_NAME statepack)
set(CPACK_PACKAGE_VENDOR "The statepack authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Vulkan render-state packager (statepack) and runtime dearchiver library")
set(CPACK_PACKAGE_CONTACT "The statepack authors <maintainers@users.noreply.h-seed-c96ac39a.example>")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)  # the RelWithDebInfo packager is ~50 MB with its debug information
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # statepack_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
# dpkg-shlibdeps finds the packager's run-time libraries (Vulkan loader, spirv-cross, libstdc++, …);
# compiling and linking against the dearchiver also needs the Vulkan headers and libxxhash.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libvulkan-dev, libxxhash-dev")
# The OpenGL runtime (statepack::gl) also needs libepoxy's headers; the Vulkan dearchiver does not. The
# packager's --remote-cache opens libcurl and hiredis when first used (dpkg-shlibdeps cannot see them).
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libepoxy-dev, libcurl4, libhiredis0.14")
include(CPack)
