# The naming and versioning every installed shared library shares
# (docs/install.md, "Versions"): libNAME.so.MAJOR.MINOR.PATCH with the
# SONAME libNAME.so.MAJOR.MINOR. While the project is at 0.x any minor
# release may change the ABI, so the SONAME carries major and minor; from
# 1.0 on it will carry the major alone.
function(sss_shared_library target name)
  if(PROJECT_VERSION_MAJOR EQUAL 0)
    set(soversion ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  else()
    set(soversion ${PROJECT_VERSION_MAJOR})
  endif()
  # $ORIGIN: an installed libsss_bake.so or libsss_render.so finds the
  # libsss.so beside it; the link path: the dependencies outside the
  # system's directories (Debian's HDF5 under FLANN, for one).
  set_target_properties(${target} PROPERTIES
    OUTPUT_NAME ${name}
    VERSION ${PROJECT_VERSION}
    SOVERSION ${soversion}
    INSTALL_RPATH "$ORIGIN"
    INSTALL_RPATH_USE_LINK_PATH ON)
endfunction()

# The objects of a library that is also built shared are compiled
# position-independent. -fno-semantic-interposition lets the compiler inline
# and call directly the library's own functions as it does without -fPIC
# (nothing is meant to interpose them), so the static libraries the tools
# link lose no speed to the shared form.
function(sss_shared_objects target)
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_compile_options(${target} PRIVATE -fno-semantic-interposition)
endfunction()
