# ctest driver: `cmake --install` the build into a scratch prefix, check the
# bundle's layout there (gdof.ofx.bundle/Contents/Info.plist and
# Contents/<arch>/gdof.ofx beside gdof_oiio.so, gdof.ofx itself without
# OpenImageIO), then run the describe tests on the installed
# binary (GDOF_OFX_BUNDLE points the test host at it).
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${GDOF_BINARY_DIR}" --prefix "${WORK_DIR}/prefix"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}):\n${out}\n${err}")
endif()
file(GLOB_RECURSE binaries "${WORK_DIR}/prefix/*gdof.ofx")
list(FILTER binaries INCLUDE REGEX "/gdof\\.ofx\\.bundle/Contents/[^/]+/gdof\\.ofx$")
list(LENGTH binaries n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "expected one installed gdof.ofx.bundle/Contents/<arch>/gdof.ofx, found ${n}: ${binaries}")
endif()
get_filename_component(arch_dir "${binaries}" DIRECTORY)
get_filename_component(contents "${arch_dir}" DIRECTORY)
if(NOT EXISTS "${contents}/Info.plist")
  message(FATAL_ERROR "no Info.plist in ${contents}")
endif()
# OpenImageIO comes only with the module beside gdof.ofx, loaded when a
# stack reference needs it: a host loading the bundle does not load it.
if(NOT EXISTS "${arch_dir}/gdof_oiio.so")
  message(FATAL_ERROR "no gdof_oiio.so beside ${binaries}")
endif()
execute_process(COMMAND ldd "${binaries}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR out MATCHES "libOpenImageIO" OR out MATCHES "not found")
  message(FATAL_ERROR "gdof.ofx must load without OpenImageIO (exit ${rc}):\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env "GDOF_OFX_BUNDLE=${binaries}" "${DESCRIBE_TEST}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the describe tests fail on the installed bundle ${binaries}:\n${out}\n${err}")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
message(STATUS "ofx_install: ${binaries} installed and loads")
