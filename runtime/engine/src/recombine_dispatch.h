// Which vector path the recombination kernels (recombine.h,
// compressed_recombine.h) and the mix take: chosen at run time from what the
// CPU and the operating system support (cpuid + xgetbv), capped by the
// environment or by tests and benchmarks, so that every path can be run and
// compared on one machine. Every path gives the same bits.
#pragma once

namespace relight {

// Ordered: a cap allows its level and the ones below it.
enum class SimdLevel : int {
  kScalar = 0,
  kAvx2 = 1,        // vpmaddwd + vpaddd, 256 bits
  kAvxVnni = 2,     // AVX-VNNI vpdpwssd (VEX), 256 bits
  kAvx512Vnni = 3,  // AVX-512 F/BW/VL + VNNI vpdpwssd, 512 bits, masked tails
};

// True when the CPU reports the level and the OS saves its registers
// (XCR0: XMM and YMM for AVX2 / AVX-VNNI, plus opmask and ZMM for AVX-512).
// Always false but for kScalar off x86-64.
bool CpuSupportsSimdLevel(SimdLevel level);

// The highest level <= the cap that the CPU supports. The cap starts as
// RELIGHT_SIMD (scalar | avx2 | avxvnni | avx512vnni; unset: no cap) or
// scalar when RELIGHT_FORCE_SCALAR is set, not empty and not "0".
// One relaxed atomic load a call: cheap next to any kernel call.
SimdLevel ActiveSimdLevel();

// Replaces the cap (tests, benchmarks); kAvx512Vnni removes it. Takes effect
// on the next kernel call; not meant to change while an Update() runs.
void SetSimdLevelCap(SimdLevel cap);

// The name RELIGHT_SIMD uses for the level ("scalar", "avx2", ...).
const char* SimdLevelName(SimdLevel level);

}  // namespace relight
