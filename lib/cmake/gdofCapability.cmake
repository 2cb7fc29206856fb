# One folder, one target per capability, and dependencies that only point
# down (lib/README.md has the map).
#
#   set(GDOF_CAP_INCLUDE_ROOT <dir>)  where the public headers live (<dir>/gdof/...)
#   set(GDOF_CAP_SOURCE_ROOT <dir>)   where the capability folders live
#   gdof_capability(<name>
#     DIR <folder>                 under GDOF_CAP_SOURCE_ROOT: sources <folder>/*.cpp,
#                                  private headers <folder>/*.h (included as "<folder>/x.h")
#     [HEADERS <public headers>]   the public headers it owns ("camera.h", "io/colour.h")
#     [DEPENDS <capabilities>]     the capabilities it may use (declared before it)
#     [PUBLIC_LIBS ...] [PRIVATE_LIBS ...])
#
# Creates the static (or shared) library gdof_<name>. At configure time every
# #include "..." of its sources and of its public headers is checked: a
# public header ("gdof/x.h") or a private one ("folder/x.h") must belong to
# the capability itself or to one it depends on, directly or through others;
# anything else stops the configure step with the offending file and line.

function(_gdof_check_includes name file allowed)
  file(STRINGS "${file}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" inc "${line}")
    if(inc MATCHES "^gdof/(.+)$")
      set(key "${CMAKE_MATCH_1}")
      get_property(owner GLOBAL PROPERTY "GDOF_HEADER_OWNER_${key}")
      if(NOT owner)
        message(FATAL_ERROR "${file}: includes \"${inc}\", which is not a public header of any capability "
                            "declared before '${name}' (dependencies must point down: lib/README.md)")
      endif()
    elseif(inc MATCHES "^([a-z_]+)/[^/]+$")
      get_property(owner GLOBAL PROPERTY "GDOF_FOLDER_OWNER_${GDOF_CAP_SOURCE_ROOT}/${CMAKE_MATCH_1}")
      if(NOT owner)
        message(FATAL_ERROR "${file}: includes \"${inc}\" from the folder '${CMAKE_MATCH_1}', "
                            "which is not a capability declared before '${name}'")
      endif()
    else()
      continue()  # same-folder or third-party quoted headers (ofx, tiny_obj)
    endif()
    if(NOT owner IN_LIST allowed)
      message(FATAL_ERROR "${file}: includes \"${inc}\" (capability '${owner}'), but '${name}' may only use: "
                          "${allowed} (lib/README.md)")
    endif()
  endforeach()
endfunction()

function(gdof_capability name)
  cmake_parse_arguments(C "" "DIR" "HEADERS;DEPENDS;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  # The transitive closure of the dependencies, plus the capability itself.
  set(allowed ${name})
  set(dep_targets "")
  foreach(dep IN LISTS C_DEPENDS)
    get_property(dep_closure GLOBAL PROPERTY "GDOF_CAP_CLOSURE_${dep}")
    if(NOT dep_closure)
      message(FATAL_ERROR "capability '${name}' depends on '${dep}', which is not declared before it")
    endif()
    list(APPEND allowed ${dep_closure})
    list(APPEND dep_targets gdof_${dep})
  endforeach()
  list(REMOVE_DUPLICATES allowed)
  set_property(GLOBAL PROPERTY "GDOF_CAP_CLOSURE_${name}" "${allowed}")

  set(dir "${GDOF_CAP_SOURCE_ROOT}/${C_DIR}")
  set_property(GLOBAL PROPERTY "GDOF_FOLDER_OWNER_${dir}" ${name})
  foreach(h IN LISTS C_HEADERS)
    set_property(GLOBAL PROPERTY "GDOF_HEADER_OWNER_${h}" ${name})
  endforeach()

  file(GLOB sources CONFIGURE_DEPENDS ${dir}/*.cpp)
  file(GLOB private_headers CONFIGURE_DEPENDS ${dir}/*.h)
  set(public_headers "")
  foreach(h IN LISTS C_HEADERS)
    list(APPEND public_headers ${GDOF_CAP_INCLUDE_ROOT}/gdof/${h})
  endforeach()
  foreach(f IN LISTS sources private_headers public_headers)
    _gdof_check_includes(${name} "${f}" "${allowed}")
  endforeach()

  add_library(gdof_${name} ${sources})
  set_target_properties(gdof_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME gdof_${name})
  target_include_directories(gdof_${name}
    PUBLIC $<BUILD_INTERFACE:${GDOF_CAP_INCLUDE_ROOT}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${GDOF_CAP_SOURCE_ROOT})
  target_link_libraries(gdof_${name} PUBLIC ${dep_targets} ${C_PUBLIC_LIBS} PRIVATE ${C_PRIVATE_LIBS} gdof_warnings)
  set_property(GLOBAL APPEND PROPERTY GDOF_CAPABILITY_TARGETS gdof_${name})
endfunction()
