# Checks shared by the host build and runtime-only (cross) builds: no heap
# after Engine::Open over a long mixed run, and bit-identical frames across
# recombination paths and targets. Both use a hierarchical bake of the living
# room made on the host by relight-bake (a runtime-only build cannot bake):
# RELIGHT_TEST_HIER_BAKE names it. The host build makes it on demand (the
# LivingRoomHierBake fixture); scripts/cross-test.sh passes the host's file
# to the cross build.
set(RELIGHT_TEST_HIER_BAKE "${CMAKE_BINARY_DIR}/test-bakes/living_room_hier.rlb"
    CACHE FILEPATH "hierarchical living-room bake for engine_no_alloc_test and the replay hash comparison")

# (relight_test's settings, plus the bake fixture on the host.)
add_executable(engine_no_alloc_test engine_no_alloc_test.cc)
target_link_libraries(engine_no_alloc_test PRIVATE relight_engine GTest::gtest GTest::gtest_main)
target_compile_options(engine_no_alloc_test PRIVATE ${RELIGHT_WARNINGS})
target_compile_definitions(engine_no_alloc_test PRIVATE RELIGHT_TEST_HIER_BAKE="${RELIGHT_TEST_HIER_BAKE}")
set(no_alloc_properties TIMEOUT 900)
if(NOT RELIGHT_RUNTIME_ONLY)
  list(APPEND no_alloc_properties FIXTURES_REQUIRED living_room_hier_bake)
endif()
gtest_discover_tests(engine_no_alloc_test DISCOVERY_TIMEOUT 120 PROPERTIES ${no_alloc_properties})

if(NOT RELIGHT_RUNTIME_ONLY)
  # Bakes the living room (hierarchical solver) unless a bake newer than
  # relight-bake is there already.
  add_test(NAME MakeLivingRoomHierBake
           COMMAND sh -c "test \"$1\" -nt \"$2\" || { mkdir -p \"$(dirname \"$1\")\" && \"$2\" \"$3\" --solver hierarchical -q -o \"$1\"; }"
                   make-bake ${RELIGHT_TEST_HIER_BAKE} $<TARGET_FILE:relight-bake>
                   ${PROJECT_SOURCE_DIR}/fixtures/living_room.toml)
  set_tests_properties(MakeLivingRoomHierBake PROPERTIES FIXTURES_SETUP living_room_hier_bake TIMEOUT 900)

  # x86-64 AVX2 against x86-64 scalar, and against aarch64 under qemu when
  # the cross build (RELIGHT_CROSS_BUILD_DIR, scripts/cross-test.sh) and
  # qemu-aarch64 are there; skipped (77) otherwise.
  set(RELIGHT_CROSS_BUILD_DIR "${PROJECT_SOURCE_DIR}/build-aarch64"
      CACHE PATH "aarch64 runtime-only build compared by ReplayHashesMatchAcrossTargets")
  add_test(NAME ReplayHashesMatchAcrossTargets
           COMMAND ${PROJECT_SOURCE_DIR}/scripts/compare-replay-hashes.sh
                   --bake ${RELIGHT_TEST_HIER_BAKE}
                   --host-tool $<TARGET_FILE:relight-replay-hash>
                   --cross-tool ${RELIGHT_CROSS_BUILD_DIR}/runtime/relight-replay-hash)
  set_tests_properties(ReplayHashesMatchAcrossTargets PROPERTIES
                       FIXTURES_REQUIRED living_room_hier_bake SKIP_RETURN_CODE 77 TIMEOUT 900)
endif()
