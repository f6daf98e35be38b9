// The one set of validation limits of a bake: the reader rejects a file
// past them (kCorrupt), the writer refuses to write one (kInvalidArgument),
// and the engine, which opens what the reader accepts, takes exactly the same
// (Engine::Open, Engine::SetLidSample). A hostile header cannot ask for more.
// Integer constants only; raw values are in the format named beside them.
#pragma once

#include <cstdint>

namespace relight::bake_format {

// --- Counts.
inline constexpr uint32_t kMaxNameBytes = 255;
inline constexpr uint32_t kMaxVertices = 1u << 26;
inline constexpr uint32_t kMaxTriangles = 1u << 27;
inline constexpr uint32_t kMaxSurfaces = 1u << 16;
inline constexpr uint32_t kMaxGrids = 64;
inline constexpr uint32_t kMaxGridPoints = 1u << 24;  // per grid
inline constexpr uint32_t kMaxLuminaires = 256;

// --- Luminous intensity distributions.
inline constexpr uint32_t kMinLidSamples = 3;
inline constexpr uint32_t kMaxLidSamples = 65537;
// Largest LID value (axisymmetric samples, (C, gamma) table values, and a
// sample edited at run time): 2^31 cd, Q48.16. Why this bound and no
// stricter one for the engine: every kernel a LID value reaches forms its
// products in 128 bits and saturates what it stores, so it takes any value
// up to here without overflow:
//   Legendre weights (legendre_weights.cc): I x f_l < 2^47 x 2^30 per sample,
//     summed over <= 2^17 samples in int128; w_l <= ~2^6 x peak = 2^53 Q48.16;
//   sigma damping and A_lm (weights.cc): w x Q1.30 in int128, < 2^56;
//   direct term (direct.h): I x g x mantissa < 2^47 x 2^32 x 2^30 = 2^109;
//   LID lookups (lid_lookup.h, lid_table.h): differences x fraction in int128;
//   recombination multipliers (weights.h): coef x mantissa in int128, k
//     clamped to int32 with the shift chosen for it.
// Outputs past LightQ12's int32 saturate (a 2^31 cd beam is far past white);
// they never wrap. The engine once used a tighter 2^24 cd of its own; that
// bound was headroom, not a kernel requirement, and is gone.
inline constexpr int64_t kMaxCandelaRaw = int64_t{1} << 47;
// A (C, gamma) table: planes 0..360 and gammas, and values in all.
inline constexpr uint32_t kMinLidPlanes = 3;
inline constexpr uint32_t kMaxLidPlanes = 1441;
inline constexpr uint32_t kMinLidGammas = 2;
inline constexpr uint32_t kMaxLidGammas = 1441;
inline constexpr uint64_t kMaxLidTableValues = uint64_t{1} << 20;
// |SH coefficient| of a (C, gamma) LID: 2^34 cd, Q48.16. A coefficient is at
// most sqrt(4 pi) < 4 x the peak, so 2^34 cd admits every table within
// kMaxCandelaRaw; RotateShQ16 (sh_rotation.h) takes |c| < 2^51.
inline constexpr int64_t kMaxShCoefficientRaw = int64_t{1} << 50;

// --- Zoom (BakeZoom): beam angles in (0, 180) degrees, Q16.16; the profile
// has 2 .. 4097 samples in [0, 1] (Q2.30), the first 1 and none rising; it
// ends at x in (1, 64] (past the half-peak point, at most 64 half beam
// angles). Lumens up to 2^32 lm (Q48.16): the engine forms
// lumens x M x 2^60 in 128 bits (engine zoom.cc).
inline constexpr int32_t kMaxZoomAngleRaw = 180 << 16;  // exclusive
inline constexpr uint32_t kMinZoomProfileSamples = 2;
inline constexpr uint32_t kMaxZoomProfileSamples = 4097;
inline constexpr int32_t kZoomProfileOne = int32_t{1} << 30;
inline constexpr int32_t kMinZoomProfileEndRaw = 1 << 16;  // exclusive
inline constexpr int32_t kMaxZoomProfileEndRaw = 64 << 16;
inline constexpr int64_t kMaxZoomLumensRaw = int64_t{1} << 48;

// --- Orientation and console ranges, Q16.16 degrees.
inline constexpr int32_t kMaxTurnRaw = 360 << 16;  // yaw, roll: [-360, 360] degrees
inline constexpr int32_t kMaxPanRangeRaw = 720 << 16;
inline constexpr int32_t kMaxTiltRangeRaw = 360 << 16;

// --- Quantisation scales (fixed.h QuantScale).
inline constexpr int32_t kMinScaleExponent = -128;
inline constexpr int32_t kMaxScaleExponent = 127;
inline constexpr int32_t kScaleMantissaMin = int32_t{1} << 29;
inline constexpr int32_t kScaleMantissaEnd = int32_t{1} << 30;

// Q1.14 unit vectors: |v|^2 (Q2.28) within 2^28 +- 2^22, i.e. |v| = 1 +- 0.8 %.
inline constexpr int64_t kUnitSquared = int64_t{1} << 28;
inline constexpr int64_t kUnitSquaredTolerance = int64_t{1} << 22;

// --- Hierarchy: an inner node has at least 2 children and a leaf at least
// one triangle, so there are fewer than 2 T nodes.
inline constexpr uint32_t kMinNodeCorners = 3;
inline constexpr uint32_t kMinChildren = 2;
inline constexpr uint64_t kMaxNodeAreaRaw = uint64_t{1} << 56;  // Q32.32: 2^24 m^2
inline constexpr uint32_t kMaxLinks = 1u << 28;

}  // namespace relight::bake_format
