# What `cmake --install` puts under the prefix (docs/install.md): the tools,
# libsss / libsss_bake / libsss_render static and shared, their public
# headers, the CMake package (find_package(sss)) and the pkg-config files.
include(CMakePackageConfigHelpers)

set(SSS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/sss)

# the tools link the static libraries; what they need beyond the system's
# directories (Debian's HDF5 under FLANN) stays found once installed
set(SSS_TOOLS sss-bake sss-stat sss-ref sss-view sss-genmesh)
set_target_properties(${SSS_TOOLS} PROPERTIES INSTALL_RPATH_USE_LINK_PATH ON)
install(TARGETS ${SSS_TOOLS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# one export set per library, both forms in each; in the package the
# shared library takes the plain name and the archive the _static one
foreach(lib sss sss_bake sss_render)
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${lib}_static)
  set_target_properties(${lib}_shared PROPERTIES EXPORT_NAME ${lib})
  string(REPLACE "_" "-" file ${lib})
  install(TARGETS ${lib} ${lib}_shared EXPORT ${lib}-targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT ${lib}-targets NAMESPACE sss:: FILE ${file}-targets.cmake DESTINATION ${SSS_CMAKE_DIR})
endforeach()

# every header under a layer's include/sss/ is public (docs/architecture.md §3–§4)
foreach(layer common precompute runtime)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${layer}/include/sss
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
endforeach()

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/sssConfig.cmake.in
  ${PROJECT_BINARY_DIR}/package/sssConfig.cmake INSTALL_DESTINATION ${SSS_CMAKE_DIR})
# 0.x: a minor release may break the ABI, so only the same major.minor is
# compatible (the SONAME rule of common/cmake/sss_library.cmake)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/sssConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/package/sssConfig.cmake ${PROJECT_BINARY_DIR}/package/sssConfigVersion.cmake
  DESTINATION ${SSS_CMAKE_DIR})

# pkg-config files relative to where they lie (${pcfiledir}), so that
# `cmake --install --prefix P` may choose any P after configuring
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  message(FATAL_ERROR "sss: CMAKE_INSTALL_LIBDIR must be relative to the prefix (pkg-config files are relocatable)")
endif()
file(RELATIVE_PATH SSS_PC_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" SSS_PC_PREFIX "${SSS_PC_PREFIX}")
set(SSS_PC_OPENMP "${OpenMP_C_FLAGS}")
foreach(pc sss sss-bake sss-render)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/${pc}.pc.in ${PROJECT_BINARY_DIR}/package/${pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/package/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()

# the Python package (docs/python.md): beside the libraries, three folders
# below the libsss.so it loads (LIBDIR/python3/dist-packages/sss)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/common/python/sss
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/python3/dist-packages FILES_MATCHING PATTERN "*.py")
