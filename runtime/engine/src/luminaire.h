// One luminaire at run time: its fixture state, its LID prepared for the
// kernels (Legendre weights, or a (C, gamma) table and SH coefficients), and
// its caches per receiver set. Set up once in Engine::Open (all buffers sized
// from the bake there); edited and recomputed without allocating.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "direct_aimed.h"
#include "lid_table.h"
#include "relight/bake/bake.h"
#include "relight/base/fixed.h"
#include "relight/base/sh_index.h"
#include "relight/base/status.h"
#include "relight/engine/engine.h"
#include "relight/engine/sh_eval.h"
#include "relight/engine/sh_rotation.h"

namespace relight {

// One receiver set's cache, LightQ12, 3 per receiver, at dimmer 1 and white.
struct SetCache {
  std::vector<int32_t> light;   // vertices: direct + indirect; grids: indirect
  std::vector<int32_t> direct;  // grids of kExactDirect luminaires
  DirectPoints direct_points;   // kExactDirect, axisymmetric LID: the aimed direct term
};

struct LuminaireRuntime {
  FixtureState state;
  bool dirty = true;
  // A zoom set since the last Update(): the LID samples and weights follow
  // state.zoom_deg when the luminaire is next rebuilt (ApplyZoom).
  bool zoom_pending = false;
  int degree = 0;
  int lid_m = 0;
  int64_t damped_weights_q16[kMaxShDegree + 1] = {};
  // Beam editing (Dobashi 4.1): the undamped weights w_l and the f_l table
  // of Eq. 20 that Eq. 21 updates them with.
  int64_t weights_q16[kMaxShDegree + 1] = {};
  std::vector<int32_t> legendre_table_q30;
  // A LID that is not axisymmetric: its (C, gamma) table for the direct term
  // and its SH coefficients in the fixture frame, sigma applied (Q48.16).
  bool has_table = false;
  LidTableView table;
  std::vector<int64_t> sh_local_q16;
  std::vector<SetCache> sets;
};

// Scratch shared by every luminaire's recomputation, sized for the largest.
struct CacheWorkspace {
  ShTables sh;
  // Only with a (C, gamma) LID; read-only after Open, shared by the
  // per-thread copies of the workspace (engine_threads.h).
  std::shared_ptr<ShRotationTables> rotation;
  std::vector<int32_t> rotation_q30;           // band matrices, kShRotationValues
  std::vector<int64_t> alm_q30, coef_q16;      // per term
  std::vector<int32_t> k;                      // per term and channel
  std::vector<int64_t> scratch;                // recombine / mix blocks
  std::vector<int32_t> compressed_projection;  // compressed bases (compressed_recombine.h)
  std::vector<int64_t> zoom_samples_q16;       // M+1 of the largest zooming LID
  std::vector<uint32_t> reflectance_over_pi_q32;  // 3 per vertex
};

// Degrees wrapped to (-180, 180].
Q16_16 WrapDegrees(Q16_16 degrees);
// Negative levels to 0.
Q1_15 ClampUnit(Q1_15 v);

// Sizes `work` (scratch for the largest receiver set and degree, rotation
// tables if any LID has planes) and every luminaire: LID prepared (Legendre
// table and damped weights, or the sigma-damped SH coefficients), default
// state, caches. The bake must have passed ValidateBake. Returns
// kInvalidArgument naming the luminaire if its LID cannot be expanded.
// release_direct_inputs: each luminaire's ReleasePreparedDirectInputs right
// after its set-up (EngineOptions::keep_direct_inputs false), so the bake's
// copy and the prepared one are held for one luminaire at a time.
Status SetUpLuminaires(Bake* bake, bool release_direct_inputs, std::vector<LuminaireRuntime>* lums,
                       CacheWorkspace* work);

// Frees the bake's per-receiver direction and geometry of a luminaire whose
// direct term now reads its DirectPoints (exact direct, axisymmetric LID):
// the kernels read only their copy after its set-up. A (C, gamma) LID keeps
// them: its direct term reads them.
void ReleasePreparedDirectInputs(BakeLuminaire* b, const LuminaireRuntime& l);

// Dobashi 4.1: sample `sample` of an axisymmetric LID moves to candela_q16;
// Eq. 21 updates the weights by its increment alone, O(N), and marks the
// luminaire dirty; *changed tells whether the sample moved. Returns kUnsupported (LID has planes), kInvalidArgument
// (sample index), kOutOfRange (candela outside [0, kMaxCandelaRaw]).
Status EditLidSample(BakeLuminaire* b, LuminaireRuntime* l, int sample, int64_t candela_q16,
                     bool* changed);

// The LID samples of l->state.zoom_deg (zoom.h) into b->lid.candela, then
// the Legendre weights from scratch (Eq. 19, not a chain of Eq. 21 updates,
// so zooming back and forth never drifts) and their damping; clears
// zoom_pending and marks the luminaire dirty. `samples` holds M+1 values.
void ApplyZoom(BakeLuminaire* b, LuminaireRuntime* l, int64_t* samples);

}  // namespace relight
