# The runtime tests that need no baker, for a runtime-only build
# (RELIGHT_RUNTIME_ONLY, e.g. the aarch64 cross build run under qemu):
# fixed-point helpers, tone map, the bake file format. Tests that bake a scene
# in-process (engine_test, surface_emitter_test, ...) are left out; the
# engine itself is covered by engine_no_alloc_test and relight-replay-hash on
# a bake made on the host (cross_checks.cmake). worker_pool_test is left
# out too: under this machine's qemu-user a program that starts one
# std::thread does not finish (checked: a bare thread-and-join, 10 s), so
# the pool runs on the host only (scripts/cross-test.sh runs one thread).
relight_test(fixed_math_test SOURCES fixed_math_test.cc LIBS relight_base)
relight_test(tone_map_test SOURCES tone_map_test.cc LIBS relight_engine)
relight_test(bake_io_test SOURCES bake_io_test.cc bake_hierarchy_io_test.cc
             LIBS relight_engine PkgConfig::ZSTD ZLIB::ZLIB)
# The renderer's RGBA -> RGB row copy has a NEON body; it needs no OSMesa, so
# it is built here from its source to run on the target.
relight_test(rgba_rows_test SOURCES rgba_rows_test.cc ${PROJECT_SOURCE_DIR}/runtime/render/src/rgba_rows.cc
             LIBS relight_base)
target_include_directories(rgba_rows_test PRIVATE ${PROJECT_SOURCE_DIR}/runtime/render/src)

# The integer-only layers' object code, for the target's instruction set.
if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64|aarch64|arm64")
  add_test(NAME RuntimeHasNoFloatingPointCode
           COMMAND env OBJDUMP=${CMAKE_OBJDUMP} sh ${CMAKE_CURRENT_SOURCE_DIR}/no_float_check.sh
                   $<TARGET_FILE:relight_base> $<TARGET_FILE:relight_bake> $<TARGET_FILE:relight_engine>)
endif()
