// What this process keeps resident, per mapping, from /proc/self/smaps: for
// tests of memory handed back to the kernel (render/compiler_pages.h).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace relight::test {

// kB summed over the chosen mappings. Private pages are mapped by this
// process only; shared ones also by another (e.g. a test running beside it).
struct SmapsKb {
  bool any = false;  // a mapping matched
  long rss = 0;
  long private_clean = 0;
  long shared_clean = 0;
};

// Every mapping whose /proc/self/smaps header line contains `path_part`
// (when non-null) or starts at `start` (when non-zero).
inline SmapsKb ReadSmapsKb(const char* path_part, uintptr_t start) {
  SmapsKb sums;
  FILE* f = std::fopen("/proc/self/smaps", "r");
  if (f == nullptr) return sums;
  char line[4096];
  bool in = false;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    uintmax_t a = 0, b = 0;
    // A header is "start-end perms ..."; field lines are "Name: value kB".
    if (std::sscanf(line, "%jx-%jx ", &a, &b) == 2 && std::strchr(line, '-') < std::strchr(line, ' ')) {
      in = (path_part != nullptr && std::strstr(line, path_part) != nullptr) || (start != 0 && a == start);
      sums.any = sums.any || in;
      continue;
    }
    if (!in) continue;
    long kb = 0;
    if (std::sscanf(line, "Rss: %ld kB", &kb) == 1) sums.rss += kb;
    if (std::sscanf(line, "Private_Clean: %ld kB", &kb) == 1) sums.private_clean += kb;
    if (std::sscanf(line, "Shared_Clean: %ld kB", &kb) == 1) sums.shared_clean += kb;
  }
  std::fclose(f);
  return sums;
}

inline SmapsKb SmapsOfPath(const char* path_part) { return ReadSmapsKb(path_part, 0); }
inline SmapsKb SmapsAt(const void* addr) { return ReadSmapsKb(nullptr, reinterpret_cast<uintptr_t>(addr)); }

}  // namespace relight::test
