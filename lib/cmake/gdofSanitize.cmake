# GDOF_SANITIZE and GDOF_FUZZ (docs/reliability.md): flags for every target
# of the build, the libraries included, so a finding points into gdof's own
# code. Errors stop at once (no recovery), so ctest sees a failure.
if(GDOF_SANITIZE)
  add_compile_options(-fsanitize=${GDOF_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all -g)
  add_link_options(-fsanitize=${GDOF_SANITIZE})
endif()
if(GDOF_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "GDOF_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # Coverage for libFuzzer in every object; the harnesses add the fuzzer's main.
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
