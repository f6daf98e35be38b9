# Cross build for 64-bit ARM Linux with Debian's g++-aarch64-linux-gnu and
# the :arm64 dev packages (libzstd-dev:arm64, zlib1g-dev:arm64,
# libgtest-dev:arm64). Tests run under qemu-aarch64 (no binfmt needed):
#   cmake -S . -B build-aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake -DRELIGHT_RUNTIME_ONLY=ON
# scripts/cross-test.sh does it all.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(RELIGHT_CROSS_TRIPLE aarch64-linux-gnu)
set(CMAKE_C_COMPILER ${RELIGHT_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${RELIGHT_CROSS_TRIPLE}-g++)

# Debian's multiarch layout: arm64 libraries in /usr/lib/aarch64-linux-gnu,
# headers shared in /usr/include; the toolchain's own sysroot is
# /usr/aarch64-linux-gnu.
set(CMAKE_FIND_ROOT_PATH /usr/${RELIGHT_CROSS_TRIPLE})
set(CMAKE_LIBRARY_ARCHITECTURE ${RELIGHT_CROSS_TRIPLE})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)

# pkg-config must see the arm64 .pc files only, not the host's.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/${RELIGHT_CROSS_TRIPLE}/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")

# ctest, gtest_discover_tests and add_test run target binaries through this.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/${RELIGHT_CROSS_TRIPLE})
