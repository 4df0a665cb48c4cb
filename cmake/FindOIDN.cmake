# Intel Open Image Denoise: tools/fetch_oidn.sh's copy of the pinned pyoidn
# wheel's libraries ($CAUSTICA_DEPS_DIR or .deps/ beside build/), else a
# system OIDN 2. Defines OIDN_FOUND and the imported target OIDN::OIDN (the
# library alone: host/denoise/oidn_api.h declares the API, since the wheel
# ships no headers). Linked by full path, so the build's RPATH finds it
# with no environment variable.
set(_oidn_deps "$ENV{CAUSTICA_DEPS_DIR}")
if(NOT _oidn_deps)
  set(_oidn_deps "${CMAKE_SOURCE_DIR}/.deps")
endif()
find_library(OIDN_LIBRARY NAMES OpenImageDenoise PATHS "${_oidn_deps}/oidn-2.5.1/lib" NO_DEFAULT_PATH)
if(NOT OIDN_LIBRARY)
  find_library(OIDN_LIBRARY NAMES OpenImageDenoise)
endif()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OIDN REQUIRED_VARS OIDN_LIBRARY)
if(OIDN_FOUND AND NOT TARGET OIDN::OIDN)
  add_library(OIDN::OIDN SHARED IMPORTED)
  set_target_properties(OIDN::OIDN PROPERTIES IMPORTED_LOCATION "${OIDN_LIBRARY}")
endif()
