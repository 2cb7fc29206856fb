# gdof_install_rpath(<target> <install dir>): with BUILD_SHARED_LIBS, where an
# installed binary finds the gdof shared libraries: $ORIGIN plus the path from
# its install dir (relative to the prefix, or absolute) to the library dir,
# so an installed tree works wherever it is moved. Nothing for static builds.
function(gdof_install_rpath target dir)
  if(NOT BUILD_SHARED_LIBS)
    return()
  endif()
  if(IS_ABSOLUTE "${dir}")
    set(rpath "${CMAKE_INSTALL_FULL_LIBDIR}")
  else()
    file(RELATIVE_PATH rel "${CMAKE_INSTALL_PREFIX}/${dir}" "${CMAKE_INSTALL_FULL_LIBDIR}")
    set(rpath "$ORIGIN")
    if(rel)
      set(rpath "$ORIGIN/${rel}")
    endif()
  endif()
  set_target_properties(${target} PROPERTIES INSTALL_RPATH "${rpath}")
endfunction()
