# find_package(OpenColorIO) with a repair for Debian bookworm's package, whose
# config file sits directly in /usr/share/cmake and therefore computes its
# install prefix as "/" (giving the include path "/include").
if(NOT TARGET OpenColorIO::OpenColorIO)
  find_package(OpenColorIO CONFIG REQUIRED PATHS /usr/share/cmake)
endif()
get_target_property(_gdof_ocio_inc OpenColorIO::OpenColorIO INTERFACE_INCLUDE_DIRECTORIES)
set(_gdof_ocio_ok TRUE)
foreach(_d IN LISTS _gdof_ocio_inc)
  if(NOT EXISTS "${_d}")
    set(_gdof_ocio_ok FALSE)
  endif()
endforeach()
if(NOT _gdof_ocio_ok)
  find_path(GDOF_OCIO_INCLUDE_DIR OpenColorIO/OpenColorIO.h REQUIRED)
  set_target_properties(OpenColorIO::OpenColorIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${GDOF_OCIO_INCLUDE_DIR}")
endif()
unset(_gdof_ocio_inc)
unset(_gdof_ocio_ok)
