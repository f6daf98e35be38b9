// A still camera's frames without the rasteriser. At a camera that does not
// move, every frame covers the same pixels with the same triangles; only the
// vertex colours change. So once per camera, from the ID pass, each pixel
// keeps which shown triangle it shows and where in it its centre lies (the
// perspective-correct barycentric weights GL's Gouraud shading uses), and a
// frame is then three weighted vertex colours per pixel: integer work in one
// sequential pass, with no triangle set-up, binning or depth test. On this
// project's 2-core box llvmpipe spent 10-13 ms on a 1280x720 stage frame; the
// resolve takes 2.5-3.8 ms on one thread, 1.7 ms on two (docs/performance.md,
// "Render: a still camera's frames resolved from a pixel table").
//
// The picture is GL's within rounding: weights are kept in 1/255 steps, so a
// pixel is within ~1 level of the float result (tests/runtime/osmesa_frame_test).
// The table's 4 bytes per pixel reuse the ID pass's RGBA buffer in place.
#pragma once

#include <cstddef>
#include <cstdint>

#include "camera.h"

namespace relight::render {

// A table entry: bits 0-15 the shown triangle's slot (its place in the
// culling's list, visible_triangles.h), bits 16-23 and 24-31 the weights of
// its second and third vertex in 1/255 (the first's is the rest).
constexpr uint32_t kResolveBackground = 0xFFFFu;  // the slot of a pixel showing nothing
constexpr uint32_t kResolveMaxSlots = 0xFFFFu;    // shown triangles one table can name
constexpr uint32_t kResolveWeightOne = 255;

// round(s / 255) for s <= 255 * 255, exactly, without a division.
inline uint32_t DivideBy255Rounded(uint32_t s) {
  const uint32_t t = s + 128;
  return (t + (t >> 8)) >> 8;
}

// The slot of every triangle from CompactVisibleTriangles' `seen` flags: shown
// triangles numbered in draw order, kResolveBackground for the others.
// Returns the number shown.
uint32_t NumberShownTriangles(const uint8_t* seen, uint32_t triangle_count, uint16_t* slot_of_triangle);

// Rewrites an ID pass (width x height RGBA, GL's bottom row first, codes as
// TriangleCode reads them) in place as the table, rows in the same order.
// positions_m: 3 floats per vertex, the positions llvmpipe drew; triangles:
// 3 vertex indices per triangle. The weights are where the ray through each
// pixel's centre meets the plane of its triangle (that is what perspective-
// correct interpolation computes), clamped into the triangle.
void BuildPixelTable(const CameraFrame& camera, int width, int height, const float* positions_m,
                     const uint32_t* triangles, const uint16_t* slot_of_triangle, uint32_t triangle_count,
                     uint8_t* id_rgba_to_table);

// A vertex colour with its channels in 16-bit fields (bits 0, 16, 32): a
// weight times it, and a sum of three such products with weights adding up
// to 255, stay inside each field, so one 64-bit multiply weighs all three
// channels (SWAR). Portable integer code: the same bits on every target.
inline uint64_t SpreadRgb(const uint8_t* rgb) {
  return uint64_t{rgb[0]} | uint64_t{rgb[1]} << 16 | uint64_t{rgb[2]} << 32;
}

// Once per frame: the three vertex colours of each of `slots` shown
// triangles (their indices 3 per slot), spread, 3 per slot.
void GatherSlotColours(const uint32_t* shown_indices, uint32_t slots, const uint8_t* vertex_rgb8,
                       uint64_t* slot_colours);

// One frame from the table and GatherSlotColours' output: out_rgb8 (top row
// first); pixels that show nothing get `background` in every channel.
void ResolvePixels(const uint8_t* table, int width, int height, const uint64_t* slot_colours, uint8_t background,
                   uint8_t* out_rgb8);

// Output rows [y_begin, y_end) only, with a chosen body: kBest is what
// ResolvePixels runs (AVX2 where the CPU has it, unless RELIGHT_FORCE_SCALAR
// is set); kAvx2 returns false, writing nothing, on a CPU or target without
// it. Every body and every split of the rows writes the same bytes, and a
// range writes only its own rows, so threads can share a frame.
enum class ResolveBody { kBest, kScalar, kAvx2 };
bool ResolveRowsWith(ResolveBody body, const uint8_t* table, int width, int height, int y_begin, int y_end,
                     const uint64_t* slot_colours, uint8_t background, uint8_t* out_rgb8);

}  // namespace relight::render
