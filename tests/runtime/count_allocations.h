// Counts heap allocations while armed, to show the engine does not allocate
// after Open. Replaces the global operator new/delete: include it from one
// source file of a test binary only.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
std::atomic<bool> g_count_allocations{false};
std::atomic<int> g_allocations{0};
}  // namespace

// Every plain form is replaced, not only the common one: under ASan a form
// left out comes from the sanitizer's runtime, and its memory then reaches
// this free() (libstdc++'s stable_sort buffer is nothrow new + delete), which
// ASan reports as an alloc-dealloc mismatch. (Aligned forms stay ASan's, new
// and delete alike.)
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  if (g_count_allocations.load()) ++g_allocations;
  return std::malloc(size ? size : 1);
}
void* operator new(std::size_t size) {
  if (void* p = operator new(size, std::nothrow)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return operator new(size, std::nothrow); }
// GCC 12 flags free() in a replaced operator delete as mismatched once
// inlined (a false positive: this operator new is malloc).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
#pragma GCC diagnostic pop
