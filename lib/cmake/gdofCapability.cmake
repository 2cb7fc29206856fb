# One folder, one target per capability, and dependencies that only point
# down (lib/README.md has the map).
#
#   set(GDOF_CAP_INCLUDE_ROOT <dir>)  where the public headers live (<dir>/gdof/...)
#   set(GDOF_CAP_SOURCE_ROOT <dir>)   where the capability folders live
#   gdof_capability(<name>
#     DIR <folder>                 under GDOF_CAP_SOURCE_ROOT: sources <folder>/*.cpp,
#                                  private headers <folder>/*.h (included as "<folder>/x.h";
#                                  a dependency's private headers are visible too, also from
#                                  another source root: io adapters use "common/json_read.h")
#     [HEADERS <public headers>]   the public headers it owns ("camera.h", "io/colour.h")
#     [DEPENDS <capabilities>]     the capabilities it may use (declared before it)
#     [PUBLIC_LIBS ...] [PRIVATE_LIBS ...])
#
# Creates the static (or, with BUILD_SHARED_LIBS, shared) library gdof_<name>. At configure time every
# #include "..." of its sources and of its public headers is checked: a
# public header ("gdof/x.h") or a private one ("folder/x.h") must belong to
# the capability itself or to one it depends on, directly or through others;
# anything else stops the configure step with the offending file and line.

# The capability owning the private header "folder/x.h": the first of the
# source roots (the capability's own first) that holds the file, else the
# owner of the folder in the first root that has such a folder.
function(_gdof_private_owner inc roots out)
  string(REGEX REPLACE "/[^/]+$" "" folder "${inc}")
  foreach(root IN LISTS roots)
    if(EXISTS "${root}/${inc}")
      get_property(owner GLOBAL PROPERTY "GDOF_FOLDER_OWNER_${root}/${folder}")
      set(${out} "${owner}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  foreach(root IN LISTS roots)
    get_property(owner GLOBAL PROPERTY "GDOF_FOLDER_OWNER_${root}/${folder}")
    if(owner)
      set(${out} "${owner}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out} "" PARENT_SCOPE)
endfunction()

function(_gdof_check_includes name file allowed roots)
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
      _gdof_private_owner("${inc}" "${roots}" owner)
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

include(${CMAKE_CURRENT_LIST_DIR}/gdofInstallRpath.cmake)

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
  # Where its private headers are looked up: its own source root, then those
  # of its dependencies (the io adapters see the core's lib/src).
  set_property(GLOBAL PROPERTY "GDOF_CAP_ROOT_${name}" "${GDOF_CAP_SOURCE_ROOT}")
  set(roots "${GDOF_CAP_SOURCE_ROOT}")
  foreach(cap IN LISTS allowed)
    get_property(root GLOBAL PROPERTY "GDOF_CAP_ROOT_${cap}")
    list(APPEND roots "${root}")
  endforeach()
  list(REMOVE_DUPLICATES roots)

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
    _gdof_check_includes(${name} "${f}" "${allowed}" "${roots}")
  endforeach()

  add_library(gdof_${name} ${sources})
  # Hidden symbols, static or shared: a shared library exports what
  # gdof/export.h's GDOF_API marks. No <target>_EXPORTS define, so a static
  # and a shared build compile every file with the same command line (ccache
  # serves one from the other).
  set_target_properties(gdof_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME gdof_${name}
    CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON DEFINE_SYMBOL ""
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  gdof_install_rpath(gdof_${name} ${CMAKE_INSTALL_LIBDIR})
  # Consumers of the installed package get C++20 from the targets themselves.
  target_compile_features(gdof_${name} PUBLIC cxx_std_20)
  target_include_directories(gdof_${name}
    PUBLIC $<BUILD_INTERFACE:${GDOF_CAP_INCLUDE_ROOT}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${roots})
  target_link_libraries(gdof_${name} PUBLIC ${dep_targets} ${C_PUBLIC_LIBS} PRIVATE ${C_PRIVATE_LIBS} gdof_warnings)
  set_property(GLOBAL APPEND PROPERTY GDOF_CAPABILITY_TARGETS gdof_${name})
endfunction()
