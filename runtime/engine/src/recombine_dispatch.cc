// Run-time choice of the kernels' vector path: see recombine_dispatch.h.
// Compiled with the SIMD objects (no -mgeneral-regs-only needed, but it
// holds no vector code: cpuid, xgetbv and an atomic int).
#include "recombine_dispatch.h"

#include <atomic>
#include <cstdlib>
#include <cstring>

#include "recombine_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#define RELIGHT_HAVE_X86_DISPATCH 1
#endif

namespace relight {
namespace {

constexpr int kLevels = 4;

#ifdef RELIGHT_HAVE_X86_DISPATCH
// XCR0 through xgetbv (ecx = 0); only called when cpuid says OSXSAVE.
uint64_t ReadXcr0() {
  uint32_t lo = 0, hi = 0;
  __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
  return (static_cast<uint64_t>(hi) << 32) | lo;
}

struct Support {
  bool level[kLevels] = {true, false, false, false};
};

Support Detect() {
  Support s;
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (!__get_cpuid(1, &a, &b, &c, &d)) return s;
  const bool osxsave = (c >> 27) & 1, avx = (c >> 28) & 1;
  if (!osxsave || !avx) return s;
  const uint64_t xcr0 = ReadXcr0();
  const bool ymm_saved = (xcr0 & 0x6) == 0x6;     // XMM, YMM
  const bool zmm_saved = (xcr0 & 0xE6) == 0xE6;   // + opmask, ZMM_Hi256, Hi16_ZMM
  if (!ymm_saved || __get_cpuid_max(0, nullptr) < 7) return s;
  __cpuid_count(7, 0, a, b, c, d);
  const bool avx2 = (b >> 5) & 1;
  const bool avx512 = ((b >> 16) & 1) && ((b >> 30) & 1) && ((b >> 31) & 1);  // F, BW, VL
  const bool avx512_vnni = (c >> 11) & 1;
  __cpuid_count(7, 1, a, b, c, d);
  const bool avx_vnni = (a >> 4) & 1;
  s.level[1] = avx2;
  s.level[2] = avx2 && avx_vnni;
  s.level[3] = avx2 && avx512 && avx512_vnni && zmm_saved;
  return s;
}
#else
struct Support {
  bool level[kLevels] = {true, false, false, false};
};
Support Detect() { return Support{}; }
#endif

const Support& Supported() {
  static const Support s = Detect();
  return s;
}

int CapFromEnvironment() {
  const char* force = std::getenv("RELIGHT_FORCE_SCALAR");
  if (force != nullptr && force[0] != '\0' && !(force[0] == '0' && force[1] == '\0')) return 0;
  const char* v = std::getenv("RELIGHT_SIMD");
  if (v == nullptr || v[0] == '\0') return kLevels - 1;
  for (int l = 0; l < kLevels; ++l) {
    if (std::strcmp(v, SimdLevelName(static_cast<SimdLevel>(l))) == 0) return l;
  }
  return kLevels - 1;  // an unknown name caps nothing (the tools print the level used)
}

// The highest supported level <= cap, cached with the cap: -1 until the first call.
std::atomic<int> g_active{-1};

int Resolve(int cap) {
  int l = cap < 0 ? 0 : (cap >= kLevels ? kLevels - 1 : cap);
  while (l > 0 && !Supported().level[l]) --l;
  return l;
}

}  // namespace

bool CpuSupportsSimdLevel(SimdLevel level) {
  const int l = static_cast<int>(level);
  return l >= 0 && l < kLevels && Supported().level[l];
}

SimdLevel ActiveSimdLevel() {
  int l = g_active.load(std::memory_order_relaxed);
  if (l < 0) {
    l = Resolve(CapFromEnvironment());
    int expected = -1;  // a concurrent first call computes the same value
    g_active.compare_exchange_strong(expected, l, std::memory_order_relaxed);
  }
  return static_cast<SimdLevel>(l);
}

void SetSimdLevelCap(SimdLevel cap) { g_active.store(Resolve(static_cast<int>(cap)), std::memory_order_relaxed); }

const char* SimdLevelName(SimdLevel level) {
  switch (level) {
    case SimdLevel::kScalar: return "scalar";
    case SimdLevel::kAvx2: return "avx2";
    case SimdLevel::kAvxVnni: return "avxvnni";
    case SimdLevel::kAvx512Vnni: return "avx512vnni";
  }
  return "?";
}

// recombine_avx2.h: kept for the mix and the emitter gather, which have AVX2 bodies only.
bool CpuHasAvx2() { return ActiveSimdLevel() >= SimdLevel::kAvx2; }

}  // namespace relight
