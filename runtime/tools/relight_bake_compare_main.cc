// relight-bake-compare: the vertex luminances of two bakes of one scene
// (e.g. compressed and uncompressed bases) through the engine, at random
// looks of the show: every luminaire at full dimmer with a random 16-bit pan
// and tilt over its console ranges, a random zoom within its range and a
// random colour; the same looks for both bakes (fixed seed).
//
//   relight-bake-compare REFERENCE.rlb OTHER.rlb [--looks 20] [--seed 1]
//
// Prints, per look and over all, the largest and the mean |OTHER - REFERENCE|
// over vertices and channels as a percentage of the look's peak (the largest
// REFERENCE value), and each bake's bases in memory against float32.
// Exit status: 0, 2 for bad arguments, 1 when a bake cannot be opened.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "relight/bake/bake.h"
#include "relight/base/sh_index.h"
#include "relight/engine/engine.h"

namespace {

using relight::Bake;
using relight::Engine;

// Bases in memory and the same values as float32.
void BasisBytes(const Bake& bake, double* bytes, double* float32) {
  *bytes = *float32 = 0;
  for (const relight::BakeLuminaire& l : bake.luminaires) {
    const double terms = relight::ShTermCount(l.sh_degree);
    for (uint32_t s = 0; s < bake.receiver_set_count(); ++s) {
      const relight::BakeLightReceivers& rx = l.receivers[s];
      *float32 += 4.0 * 3 * terms * bake.receiver_count(s);
      *bytes += rx.compressed.present() ? static_cast<double>(rx.compressed.memory_bytes())
                                        : static_cast<double>(2 * rx.basis.size() + 8 * rx.basis_scale.size());
    }
  }
}

// One look: the same random state on both engines.
void SetLook(std::mt19937* rng, Engine* a, Engine* b) {
  std::uniform_int_distribution<int> u16(0, 65535);
  std::uniform_int_distribution<int> level(0, 32767);
  for (int l = 0; l < a->luminaire_count(); ++l) {
    const auto pan = static_cast<uint16_t>(u16(*rng)), tilt = static_cast<uint16_t>(u16(*rng));
    const relight::Q1_15 r = relight::Q1_15::FromRaw(static_cast<int16_t>(level(*rng)));
    const relight::Q1_15 g = relight::Q1_15::FromRaw(static_cast<int16_t>(level(*rng)));
    const relight::Q1_15 bl = relight::Q1_15::FromRaw(static_cast<int16_t>(level(*rng)));
    const relight::BakeZoom& zoom = a->bake().luminaires[static_cast<size_t>(l)].zoom;
    std::uniform_int_distribution<int32_t> zoom_deg(zoom.min_deg, zoom.present() ? zoom.max_deg : zoom.min_deg);
    const relight::Q16_16 z = relight::Q16_16::FromRaw(zoom_deg(*rng));
    for (Engine* e : {a, b}) {
      (void)e->SetPanTilt16(l, pan, tilt);
      (void)e->SetDimmer(l, relight::Q1_15::FromRaw(32767));
      (void)e->SetColour(l, r, g, bl);
      if (zoom.present()) (void)e->SetZoom(l, z);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  int looks = 20;
  unsigned seed = 1;
  std::string paths[2];
  int given = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--looks") == 0 && i + 1 < argc) {
      looks = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--seed") == 0 && i + 1 < argc) {
      seed = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    } else if (given < 2 && argv[i][0] != '-') {
      paths[given++] = argv[i];
    } else {
      given = -1;
      break;
    }
  }
  if (given != 2 || looks < 1) {
    std::fprintf(stderr, "usage: relight-bake-compare REFERENCE.rlb OTHER.rlb [--looks N] [--seed S]\n");
    return 2;
  }
  Engine a, b;
  relight::EngineOptions options;
  options.emitter_bounce_table_bytes = 0;  // compares the bases: no emitters are placed
  for (int k = 0; k < 2; ++k) {
    const relight::Status st = (k == 0 ? a : b).Open(paths[k], options);
    if (!st.ok()) {
      std::fprintf(stderr, "relight-bake-compare: %s: %s\n", paths[k].c_str(), st.ToString().c_str());
      return 1;
    }
  }
  if (a.vertex_count() != b.vertex_count() || a.luminaire_count() != b.luminaire_count()) {
    std::fprintf(stderr, "relight-bake-compare: the bakes differ in vertices or luminaires\n");
    return 1;
  }
  for (int k = 0; k < 2; ++k) {
    double bytes = 0, float32 = 0;
    BasisBytes((k == 0 ? a : b).bake(), &bytes, &float32);
    std::printf("%s: bases %.2f MB in memory, %.1fx vs float32 (%.2f MB)\n", paths[k].c_str(),
                bytes / 1048576.0, float32 / bytes, float32 / 1048576.0);
  }
  std::mt19937 rng(seed);
  double worst = 0, mean_sum = 0;
  const size_t n = size_t{a.vertex_count()} * 3;
  for (int look = 0; look < looks; ++look) {
    SetLook(&rng, &a, &b);
    a.Update();
    b.Update();
    const int32_t* va = a.vertex_luminance().raw();
    const int32_t* vb = b.vertex_luminance().raw();
    double peak = 0, max_err = 0, sum = 0;
    for (size_t i = 0; i < n; ++i) {
      const double ref = va[i], d = std::abs(static_cast<double>(vb[i]) - ref);
      if (ref > peak) peak = ref;
      if (d > max_err) max_err = d;
      sum += d;
    }
    const double max_pct = peak > 0 ? 100 * max_err / peak : 0;
    const double mean_pct = peak > 0 ? 100 * sum / static_cast<double>(n) / peak : 0;
    std::printf("look %2d: peak %.1f cd/m^2, max %.3f %% / mean %.4f %% of peak\n", look,
                peak / 4096.0, max_pct, mean_pct);
    if (max_pct > worst) worst = max_pct;
    mean_sum += mean_pct;
  }
  std::printf("over %d looks: max %.3f %% / mean %.4f %% of peak\n", looks, worst, mean_sum / looks);
  return 0;
}
