# Sanitizer and fuzzer builds (issue 17, docs/security.md).
#
# RELIGHT_SANITIZE=address,undefined (the `asan` preset, CMakePresets.json):
# every target is built and linked with those sanitizers, and a finding stops
# the program (-fno-sanitize-recover=all) so a test that trips one fails.
# GCC or clang. scripts/sanitize-test.sh runs the suite with it and with the
# suppressions in tests/sanitizers/.
#
# RELIGHT_FUZZ=ON (clang only): libFuzzer targets in tests/fuzz/. Every
# library is built with -fsanitize=fuzzer-no-link plus address,undefined (the
# coverage the fuzzer steers by) and each target links -fsanitize=fuzzer.
# Without it the same targets build as plain corpus-replay tests.

set(RELIGHT_SANITIZE "" CACHE STRING "Sanitizers for every target, e.g. address,undefined (empty: none)")
option(RELIGHT_FUZZ "Build the libFuzzer targets in tests/fuzz (clang only)" OFF)

if(RELIGHT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "RELIGHT_FUZZ=ON needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang")
  endif()
  if(RELIGHT_SANITIZE STREQUAL "")
    set(RELIGHT_SANITIZE "address,undefined" CACHE STRING "" FORCE)
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

# Sources no fuzz target reaches (the baker's solvers: the baker's fuzzers
# stop after parsing and meshing) lose the coverage instrumentation. It does
# nothing for them but cost: the tests of the same tree spend most of their
# time in these solvers, and with it the hierarchical Cornell bake ran 4.1x
# slower under ASan (44.8 s against 11.0 s). They keep ASan and UBSan.
function(relight_no_fuzz_coverage)
  if(RELIGHT_FUZZ)
    set_property(SOURCE ${ARGN} APPEND PROPERTY COMPILE_OPTIONS -fno-sanitize=fuzzer-no-link)
  endif()
endfunction()
# The same for whole targets (every test binary: a test is no fuzz target).
function(relight_no_fuzz_coverage_target target)
  if(RELIGHT_FUZZ)
    target_compile_options(${target} PRIVATE -fno-sanitize=fuzzer-no-link)
  endif()
endfunction()

if(NOT RELIGHT_SANITIZE STREQUAL "")
  add_compile_options(-fsanitize=${RELIGHT_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${RELIGHT_SANITIZE})
  # GCC 12's ASan instrumentation hides initialisations from its flow
  # analysis: -Wmaybe-uninitialized then fires on correct code (libstdc++'s
  # <regex>, loops that fill an array before reading it). The normal build
  # keeps the warning; this one would fail on it under RELIGHT_WERROR.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-maybe-uninitialized)
  endif()
endif()
