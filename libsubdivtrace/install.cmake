# `cmake --install BUILD [--prefix P] [--component subdivtrace_dev]`: the
# public headers, the static library and a CMake package, so another program
# can `find_package(subdivtrace)` and link `subdivtrace::subdivtrace`
# (examples/trace_rays is built that way by a test). The CLI is the
# `subdivtrace_cli` component.
include(CMakePackageConfigHelpers)

set(SUBDIVTRACE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/subdivtrace)
# Users compile the headers with C++17 too.
target_compile_features(subdivtrace PUBLIC cxx_std_17)

install(TARGETS subdivtrace EXPORT subdivtraceTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT subdivtrace_dev)
install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/subdivtrace
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT subdivtrace_dev)
install(EXPORT subdivtraceTargets NAMESPACE subdivtrace::
    DESTINATION ${SUBDIVTRACE_CMAKE_DIR} COMPONENT subdivtrace_dev)

configure_package_config_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/subdivtraceConfig.cmake.in
    ${CMAKE_CURRENT_BINARY_DIR}/subdivtraceConfig.cmake
    INSTALL_DESTINATION ${SUBDIVTRACE_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/subdivtraceConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/subdivtraceConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/subdivtraceConfigVersion.cmake
    DESTINATION ${SUBDIVTRACE_CMAKE_DIR} COMPONENT subdivtrace_dev)

install(TARGETS subdivtrace_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
    COMPONENT subdivtrace_cli)
# The image module `render` loads when it writes an image (found as
# <bindir>/../<libdir>/subdivtrace/libsubdivtrace_image.so, or in the prefix
# the build was configured with).
install(TARGETS subdivtrace_image LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/subdivtrace
    COMPONENT subdivtrace_cli)
