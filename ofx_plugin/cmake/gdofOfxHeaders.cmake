# The OpenFX 1.4 C headers the plugin is compiled against. They are never
# committed: -DOFX_INCLUDE_DIR names a folder holding them, otherwise they come
# from the crates.io package ofx_sys 0.2.0 (its native/openfx/include folder):
#
#   1. `cargo fetch` of a one-line manifest generated in the build tree, with a
#      private CARGO_HOME there (reproducible, independent of ~/.cargo) and the
#      sparse registry protocol;
#   2. if cargo is absent or fails: the .crate archive (a .tar.gz) downloaded
#      from static.crates.io with file(DOWNLOAD), its SHA-256 checked, then
#      extracted.
#
# Either way the result is cached in the build tree; a reconfigure reuses it.
# If neither works the configure fails, naming OFX_INCLUDE_DIR.

set(OFX_INCLUDE_DIR "" CACHE PATH
    "Folder with the OpenFX 1.4 C headers (ofxImageEffect.h ...); empty: obtain crates.io ofx_sys 0.2.0")
option(GDOF_OFX_USE_CARGO "Obtain ofx_sys with cargo fetch before trying a plain download" ON)

set(GDOF_OFX_SYS_VERSION 0.2.0)
set(GDOF_OFX_SYS_SHA256 0cef84cae208784242a60ce89d2b99cdc4a204eccd8e4ddddaa614fca2b2c5f5)
set(GDOF_OFX_SYS_URL "https://static.crates.io/crates/ofx_sys/ofx_sys-${GDOF_OFX_SYS_VERSION}.crate" CACHE STRING
    "Where the ofx_sys .crate is downloaded from when cargo is absent or fails (a mirror; the SHA-256 is checked)")

# Sets ${out_var} to the first folder matching the globs that holds
# ofxImageEffect.h, or to "" if none does.
function(_gdof_ofx_headers_in out_var)
  file(GLOB found LIST_DIRECTORIES true ${ARGN})
  foreach(dir IN LISTS found)
    if(EXISTS "${dir}/ofxImageEffect.h")
      set(${out_var} "${dir}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out_var} "" PARENT_SCOPE)
endfunction()

# Sets ${out_var} to the folder with ofxImageEffect.h, or fails the configure.
function(gdof_ofx_headers out_var)
  if(OFX_INCLUDE_DIR)
    if(NOT EXISTS "${OFX_INCLUDE_DIR}/ofxImageEffect.h")
      message(FATAL_ERROR "OFX_INCLUDE_DIR='${OFX_INCLUDE_DIR}' has no ofxImageEffect.h: "
                          "give the folder that holds the OpenFX 1.4 C headers")
    endif()
    set(${out_var} "${OFX_INCLUDE_DIR}" PARENT_SCOPE)
    return()
  endif()

  set(work "${CMAKE_BINARY_DIR}/_deps/ofx_sys")
  set(rel "ofx_sys-${GDOF_OFX_SYS_VERSION}/native/openfx/include")
  # Already obtained by an earlier configure (either way)?
  _gdof_ofx_headers_in(found "${work}/cargo_home/registry/src/*/${rel}" "${work}/crate/${rel}")
  if(found)
    set(${out_var} "${found}" PARENT_SCOPE)
    return()
  endif()

  set(why "")
  # 1. cargo fetch with a private CARGO_HOME.
  if(GDOF_OFX_USE_CARGO)
    find_program(GDOF_CARGO cargo HINTS "$ENV{CARGO_HOME}/bin" "$ENV{HOME}/.cargo/bin")
  endif()
  if(GDOF_OFX_USE_CARGO AND GDOF_CARGO)
    message(STATUS "gdof OFX: cargo fetch of crates.io ofx_sys ${GDOF_OFX_SYS_VERSION} (${GDOF_CARGO})")
    file(MAKE_DIRECTORY "${work}/manifest/src")
    file(WRITE "${work}/manifest/Cargo.toml"
         "[package]\nname = \"gdof_ofx_headers\"\nversion = \"0.0.0\"\nedition = \"2021\"\n"
         "[lib]\npath = \"src/lib.rs\"\n"
         "[dependencies]\nofx_sys = \"=${GDOF_OFX_SYS_VERSION}\"\n")
    file(WRITE "${work}/manifest/src/lib.rs" "")
    # Only this platform's dependencies (ofx_sys' build dependencies pull in
    # Windows crates otherwise: 170 MB instead of 30 MB).
    set(target "")
    if(CMAKE_SYSTEM_NAME STREQUAL "Linux" AND CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|aarch64)$")
      set(target --target ${CMAKE_SYSTEM_PROCESSOR}-unknown-linux-gnu)
    endif()
    execute_process(
      COMMAND ${CMAKE_COMMAND} -E env "CARGO_HOME=${work}/cargo_home" CARGO_REGISTRIES_CRATES_IO_PROTOCOL=sparse
              CARGO_NET_RETRY=3 CARGO_TERM_COLOR=never
              "${GDOF_CARGO}" fetch --manifest-path "${work}/manifest/Cargo.toml" ${target}
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 600)
    _gdof_ofx_headers_in(found "${work}/cargo_home/registry/src/*/${rel}")
    if(found)
      set(${out_var} "${found}" PARENT_SCOPE)
      return()
    endif()
    string(STRIP "${err}" err)
    set(why "cargo fetch failed (exit ${rc}): ${err}; ")
    message(STATUS "gdof OFX: ${why}trying a plain download")
  elseif(GDOF_OFX_USE_CARGO)
    set(why "cargo not found; ")
  endif()

  # 2. Download the .crate (tar.gz) and extract the headers.
  set(archive "${work}/ofx_sys-${GDOF_OFX_SYS_VERSION}.crate")
  message(STATUS "gdof OFX: downloading ${GDOF_OFX_SYS_URL}")
  file(DOWNLOAD "${GDOF_OFX_SYS_URL}" "${archive}" TLS_VERIFY ON STATUS st INACTIVITY_TIMEOUT 60 TIMEOUT 600)
  list(GET st 0 code)
  list(GET st 1 msg)
  set(sha "")
  if(code EQUAL 0)
    file(SHA256 "${archive}" sha)
  endif()
  if(code EQUAL 0 AND sha STREQUAL GDOF_OFX_SYS_SHA256)
    file(REMOVE_RECURSE "${work}/crate")
    file(ARCHIVE_EXTRACT INPUT "${archive}" DESTINATION "${work}/crate" PATTERNS "${rel}")
    if(EXISTS "${work}/crate/${rel}/ofxImageEffect.h")
      set(${out_var} "${work}/crate/${rel}" PARENT_SCOPE)
      return()
    endif()
    set(why "${why}the downloaded archive has no ${rel}/ofxImageEffect.h")
  elseif(code EQUAL 0)
    set(why "${why}${GDOF_OFX_SYS_URL} has SHA-256 ${sha}, expected ${GDOF_OFX_SYS_SHA256}")
  else()
    set(why "${why}download of ${GDOF_OFX_SYS_URL} failed: ${msg}")
  endif()
  file(REMOVE "${archive}")
  message(FATAL_ERROR
    "gdof OFX plugin: cannot obtain the OpenFX 1.4 C headers (${why}).\n"
    "Give -DOFX_INCLUDE_DIR=/path/to/openfx/include (the folder with ofxImageEffect.h), "
    "or configure with -DGDOF_BUILD_OFX=OFF.")
endfunction()
