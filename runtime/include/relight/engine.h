// The run-time engine: fixture state -> per-term weights -> fixed-point
// recombination -> per-vertex luminance (and grid illuminance).
//
//   Engine engine;
//   Status st = engine.Open("living_room.rlb");   // the only allocation
//   engine.SetPanTilt(0, Q16_16::FromInt(30), Q16_16::FromInt(45));
//   engine.Update();                               // integer-only, no heap
//   const int32_t* rgb = engine.vertex_luminance(); // LightQ12 cd/m^2, 3 per vertex
//
// Caching: each luminaire keeps its own un-dimmed, white-light result
// (direct + indirect, per channel). A pan/tilt change recomputes only that
// luminaire's cache (its SH terms and direct term); a dimmer or colour change
// re-sums the caches, O(vertices x luminaires), no SH term touched.
//
// Thread safety: none; one thread drives an Engine. Errors are Status values;
// no call throws.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "relight/bake.h"
#include "relight/fixed.h"
#include "relight/status.h"

namespace relight {

struct FixtureState {
  Q16_16 pan_deg;
  Q16_16 tilt_deg;
  Q1_15 dimmer;      // 0 .. 1
  Q1_15 rgb[3];      // 0 .. 1 each
};

class Engine {
 public:
  Engine();
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Reads and validates the bake, sizes every buffer, sets every fixture to
  // the bake's defaults and computes the first result. Returns the codes of
  // ReadBake(). On error the engine stays closed (or keeps its previous bake).
  Status Open(const std::string& bake_path);
  Status Open(Bake bake);
  bool is_open() const;

  const Bake& bake() const;
  int luminaire_count() const;
  // Index of the luminaire called `name`, or -1.
  int FindLuminaire(const std::string& name) const;

  // Setters validate and store; nothing is computed until Update().
  // kInvalidArgument for a bad index; values are clamped to their documented
  // range (dimmer and colour to [0, 1]); angles wrap.
  Status SetPanTilt(int luminaire, Q16_16 pan_deg, Q16_16 tilt_deg);
  Status SetDimmer(int luminaire, Q1_15 level);
  Status SetColour(int luminaire, Q1_15 r, Q1_15 g, Q1_15 b);
  FixtureState state(int luminaire) const;

  // Brings the outputs up to date with the state. Integer-only, no allocation.
  void Update();

  // Per vertex RGB luminance, LightQ12 cd/m^2 (1 LSB = 1/4096 cd/m^2), 3 per vertex.
  const int32_t* vertex_luminance() const;
  uint32_t vertex_count() const;
  // Per point RGB illuminance on calculation grid `grid`, LightQ12 lux,
  // 3 per point: total and direct only.
  const int32_t* grid_illuminance(int grid) const;
  const int32_t* grid_direct_illuminance(int grid) const;

  // Counters for tests and benchmarks: how many luminaire caches were rebuilt
  // by the last Update(), and how many SH term passes that took.
  int last_update_luminaires_recombined() const;
  int last_update_terms_recombined() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight
