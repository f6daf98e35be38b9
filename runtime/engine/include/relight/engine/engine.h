// The run-time engine: fixture state -> per-term weights -> fixed-point
// recombination -> per-vertex luminance (and grid illuminance).
//
//   Engine engine;
//   Status st = engine.Open("living_room.rlb");   // the only allocation
//   engine.SetPanTilt(0, Q16_16::FromInt(30), Q16_16::FromInt(45));
//   engine.Update();                               // integer-only, no heap
//   LuminanceView rgb = engine.vertex_luminance(); // LightQ12 cd/m^2 per vertex and channel
//
// Caching: each luminaire keeps its own un-dimmed, white-light result
// (direct + indirect, per channel). A pan/tilt change recomputes only that
// luminaire's cache (its SH terms and direct term); a dimmer or colour change
// re-sums the caches, O(vertices x luminaires), no SH term touched.
//
// Threads: Open starts a fixed pool of worker threads (EngineOptions), and
// Update() spreads its work over them and the calling thread, returning when
// all are done: the luminaires that changed are rebuilt in parallel and the
// remix is split by receiver ranges, with outputs bit for bit those of one
// thread. The pool stops in ~Engine (or the next Open).
// Thread safety: the Engine object itself is not thread-safe; one thread
// drives it (setters, Update, outputs), and no output may be read while
// Update() runs. Errors are Status values; no call throws.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "relight/bake/bake.h"
#include "relight/base/fixed.h"
#include "relight/base/fixture_state.h"
#include "relight/base/light_view.h"
#include "relight/base/status.h"
#include "relight/engine/surface_emitter.h"

namespace relight {

struct EngineOptions {
  // Threads Update() uses, the caller's included: 1 .. 16; 0 picks
  // RELIGHT_THREADS from the environment if set, else the hardware's,
  // capped at 2. Each thread beyond the first costs a copy of the
  // engine's scratch (a few times the largest receiver set x 3 x 8 bytes).
  int threads = 0;
  // New links one adaptive-refine emitter placement may make (8 bytes each,
  // allocated at Open); a placement needing more is refused with kOutOfRange.
  int emitter_refine_links = kDefaultSurfaceEmitterRefineLinks;
  // Adaptive refine's threshold, 2^-bits of the emitter's exitance, 0..32:
  // more bits, more new links (slower placements), nearer the exact first
  // shot (kDefaultSurfaceEmitterRefineBits).
  int emitter_refine_bits = kDefaultSurfaceEmitterRefineBits;
  // Memory (bytes) for what a new emitter's light does after its first
  // bounce, tabulated at Open over coarse pieces of every surface (one solve
  // each: ~3 s and 26 MB on the 16k-patch living room); a new emitter's
  // solve then starts near its answer and takes fewer sweeps. Scenes too
  // large for it get coarser pieces; <= 0: no table.
  int64_t emitter_bounce_table_bytes = kDefaultEmitterBounceTableBytes;
  // Answer now, settle later (needs the table above): an adaptive-refine move
  // is shown at once from its start -- the previous solution, the exact
  // change of emission and first bounce, the table's change of later
  // bounces, without a sweep -- and solved in full at the next Update() that
  // changes no emitter (an idle frame). Only within 1/32 of the table's
  // source side of where the emitter was last solved in full (further moves
  // are solved at once). false: every change is solved in full at once.
  bool emitter_quick_changes = true;
  // false: the bake's radiosity hierarchy is neither read nor kept and no
  // emitter buffers are sized (SetSurfaceEmitter answers kUnsupported). On a
  // hierarchical bake that is most of the engine's memory: relightd opens
  // this way when its patch has no [[emitter]].
  bool surface_emitters = true;
  // false: once an axisymmetric luminaire's direct term has its own copy of
  // the per-receiver direction and geometry (direct_aimed.h), the bake's are
  // freed (9 MB on the 48-head stage); bake() then holds them empty, so it is
  // no longer a whole bake to open again or write. relightd opens this way.
  bool keep_direct_inputs = true;
  // false: the bake's calculation grids are dropped at Open (their bases,
  // caches and grid links): nothing is computed for them and
  // grid_illuminance() answers empty views. 5 MB on the 48-head stage; relightd, which shows no grid, opens
  // this way.
  bool grids = true;
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
  Status Open(const std::string& bake_path, const EngineOptions& options);
  Status Open(Bake bake, const EngineOptions& options);
  bool is_open() const;
  // Threads Update() runs on (the caller's included); 0 when closed.
  int thread_count() const;

  // The bake as the engine holds it (see EngineOptions::keep_direct_inputs
  // and surface_emitters for what it may have dropped).
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
  // The fixture turned about its beam axis (bake.h "fixture frame"); wraps.
  Status SetRoll(int luminaire, Q16_16 roll_deg);
  // Zoom (bake.h BakeZoom): the full beam angle at half peak, degrees. The
  // angle is clamped to the bake's zoom range (a console's zoom channel
  // spans the lens's range; past it is the stop); the luminaire's lumens
  // stay as they are, so a narrower beam is brighter. At the next Update()
  // (or the next lid_samples() / LID edit) the LID samples become the
  // profile at the new angle and the Legendre weights are recomputed from
  // them (Dobashi Eq. 19), which the exact direct term and the SH terms then
  // use, as after a beam edit (which a later zoom replaces: the samples are
  // rebuilt from the bake's profile). Integer-only, no allocation.
  // kInvalidArgument for a bad index, kUnsupported for a luminaire without a zoom.
  Status SetZoom(int luminaire, Q16_16 beam_angle_deg);
  // Console-style 16-bit pan and tilt (coarse << 8 | fine), spread over the
  // luminaire's pan and tilt ranges (bake.h), 32768 = home (0 degrees).
  Status SetPanTilt16(int luminaire, uint16_t pan, uint16_t tilt);
  // Aims the beam at a world point (Q16.16 metres; Dobashi 4.2 with a point
  // picked in the rendered view, relight/pick.h): of the pan/tilt pairs that
  // reach it, the one inside the luminaire's console ranges nearest its
  // current aim. kInvalidArgument for a bad index or the luminaire's own
  // position, kOutOfRange when the ranges cannot reach the point.
  Status AimAt(int luminaire, const int32_t target_q16[3]);

  // Beam editing (Dobashi 4.1) of an axisymmetric LID, sampled at M+1 angles
  // gamma_k = 180 k / M (bake.h). Moving sample k (a control point, as in the
  // paper's Eq. 21) updates the Legendre weights by its increment alone and
  // the exact direct term reads the new sample; the luminaire is rebuilt at
  // the next Update(). No allocation. kInvalidArgument for a bad index,
  // kOutOfRange for candela outside [0, 2^31] (bake_limits.h kMaxCandelaRaw,
  // the file format's own bound), kUnsupported for a LID with
  // C planes (its SH coefficients come from the bake).
  Status SetLidSample(int luminaire, int k, Q48_16 candela);
  // The LID becomes the polyline through `count` control points (gamma from
  // 0, strictly increasing, at most 180; 0 past the last): every sample that
  // changes is one Eq. 21 update.
  Status SetLidControlPoints(int luminaire, const Q16_16* gamma_deg, const Q48_16* candela,
                             int count);
  // The current samples (Q48.16 cd) and their count, or nullptr.
  const int64_t* lid_samples(int luminaire, int* count) const;
  FixtureState state(int luminaire) const;

  // Run-time light sources on surfaces (relight/surface_emitter.h; Chandran &
  // Srivastava's fractional emissivity or adaptive refine, per shape), in
  // slots 0 .. kMaxSurfaceEmitters-1.
  // SetSurfaceEmitter places or moves one and sets its luminance (LightQ12
  // cd/m^2 per channel): it clips the polygon against its surface's quadtree
  // now and re-solves radiosity over the bake's links at the next Update()
  // (the only costly step). Its light is added to vertex_luminance() and, when
  // the bake has links from its nodes to the grid points (format version 6,
  // GLNK), to grid_illuminance(): both the light straight from the emitter
  // and its interreflections, for they arrive through the same node
  // exitance; grid_direct_illuminance() stays the luminaires' exact direct
  // term. Older hierarchy bakes light the grids from luminaires only.
  // Returns kUnsupported
  // (bake without a hierarchy), kNotFound (no such surface), kInvalidArgument
  // (slot, negative luminance, a corner off the surface's plane, a polygon
  // not convex or not on the surface), kOutOfRange (adaptive refine needs
  // more new links than EngineOptions::emitter_refine_links); on error
  // nothing changes. Adaptive refine computes its new links here.
  Status SetSurfaceEmitter(int slot, const SurfaceEmitterShape& shape, const LightQ12 luminance[3]);
  // A dimmer or colour change: rescales the solved light, no clip or solve.
  // Both return kUnsupported (no hierarchy) or kInvalidArgument (slot; negative
  // luminance). Removing an empty slot is not an error.
  Status SetSurfaceEmitterLuminance(int slot, const LightQ12 luminance[3]);
  Status RemoveSurfaceEmitter(int slot);

  // Brings the outputs up to date with the state. Integer-only, no allocation.
  // An Update() that changes no emitter settles the emitters shown from their
  // quick answer (EngineOptions::emitter_quick_changes).
  void Update();
  // False while an emitter's light is a quick answer the next Update() will
  // settle: a caller that updates only on input should call Update() again.
  bool emitters_settled() const;

  // Per vertex RGB luminance, LightQ12 cd/m^2 (1 LSB = 1/4096 cd/m^2); an
  // empty view when closed. Views stay valid until the next Open.
  LuminanceView vertex_luminance() const;
  uint32_t vertex_count() const;
  // Per point RGB illuminance on calculation grid `grid`, LightQ12 lux:
  // total (luminaires and run-time emitters) and the luminaires' direct
  // only; an empty view for a bad index or when closed.
  IlluminanceView grid_illuminance(int grid) const;
  IlluminanceView grid_direct_illuminance(int grid) const;

  // Counters for tests and benchmarks: how many luminaire caches were rebuilt
  // by the last Update(), and how many SH term passes that took.
  int last_update_luminaires_recombined() const;
  int last_update_terms_recombined() const;
  // Emitters solved by the last Update() and the sweeps they took (3 channels a sweep).
  int last_update_emitters_solved() const;
  int last_update_emitter_sweeps() const;
  // Of those, answered from their start without a sweep (left to settle).
  int last_update_emitters_quick() const;
  // The later-bounce table built at Open (EngineOptions::emitter_bounce_table_bytes):
  // how many coarse sources it holds and its size in bytes (0, 0 without one).
  int emitter_bounce_sources() const;
  int64_t emitter_bounce_table_size() const;
  // How far an adaptive-refine emitter may move from where it was last
  // solved in full and still be answered without a sweep, Q16 metres (0: never).
  int32_t emitter_quick_reach_q16() const;
  // New links the last adaptive-refine placement made.
  int last_emitter_refine_links() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight
