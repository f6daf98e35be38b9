// FE coverage by polygon clipping (surface_emitter_coverage.h).
//
// Scaling and overflow: positions are Q16.16 metres (|x| < 2^31). In the
// projected plane the emitter's corners stay Q16.16; node corners and clipped
// points are Q.32 (int64, |x| < 2^47). A side test is (emitter edge, Q16.16,
// < 2^32) x (point - edge start, Q.32, < 2^49): < 2^82 in Int128. The crossing
// parameter t is Q.40 (side << 40 < 2^122); a clipped point moves by at most
// |edge| 2^-40. Twice an area is a sum of < 16 products of Q.32 coordinates
// relative to the first point: < 2^103.
#include "surface_emitter_coverage.h"

#include "relight/base/fixed_math.h"
#include "relight/engine/surface_emitter.h"
#include "surface_emitter_frame.h"

namespace relight {
namespace {

constexpr int kCornerShift = 16;  // Q16.16 -> Q.32
constexpr int kCrossingFracBits = 40;
constexpr int kMaxClipped = kBakeMaxNodeCorners + kMaxSurfaceEmitterCorners + 2;

struct Point2 {
  int64_t x, y;
};

Int128 Abs128(Int128 v) { return v < 0 ? -v : v; }

// The emitter in the projected plane, counter-clockwise, and the axes kept.
struct Clipper {
  const BakeHierarchy* h;
  const BakeMesh* mesh;
  int axis_a, axis_b;
  Point2 emitter[kMaxSurfaceEmitterCorners];  // Q16.16
  int count;
  bool any = false;

  Point2 Project(uint32_t vertex) const {
    const int32_t* p = &mesh->positions[3 * size_t{vertex}];
    return {p[axis_a], p[axis_b]};
  }
  // > 0 left of (inside) emitter edge e; point in Q.32.
  Int128 Side(int e, Point2 p) const {
    const Point2 a = emitter[e], b = emitter[(e + 1) % count];
    return static_cast<Int128>(b.x - a.x) * (p.y - a.y * (int64_t{1} << kCornerShift)) -
           static_cast<Int128>(b.y - a.y) * (p.x - a.x * (int64_t{1} << kCornerShift));
  }
  Point2 Corner32(uint32_t node, int k) const {
    const Point2 p = Project(h->node_corners[size_t{node} * kBakeMaxNodeCorners + static_cast<size_t>(k)]);
    return {p.x * (int64_t{1} << kCornerShift), p.y * (int64_t{1} << kCornerShift)};
  }
  // 0: no corner inside some edge's half plane (outside); 2: all corners
  // inside every edge (covered); 1: neither.
  int Classify(uint32_t node) const {
    const int n = h->node_corner_count[node];
    bool all_inside = true;
    for (int e = 0; e < count; ++e) {
      int inside = 0;
      for (int k = 0; k < n; ++k) inside += Side(e, Corner32(node, k)) >= 0 ? 1 : 0;
      if (inside == 0) return 0;
      if (inside < n) all_inside = false;
    }
    return all_inside ? 2 : 1;
  }
  void CoverAll(uint32_t node, int64_t* out) {
    if (h->leaf(node)) {
      out[node] = int64_t{1} << kCoverageFracBits;
      any = true;
      return;
    }
    const uint32_t first = h->node_first_child[node];
    for (uint32_t c = first; c < first + h->node_child_count[node]; ++c) CoverAll(c, out);
  }
  void Cover(uint32_t node, int64_t* out);
  int64_t LeafFractionQ32(uint32_t leaf) const;
};

Int128 TwiceArea(const Point2* p, int n) {
  Int128 sum = 0;
  for (int i = 1; i + 1 < n; ++i) {
    sum += static_cast<Int128>(p[i].x - p[0].x) * (p[i + 1].y - p[0].y) -
           static_cast<Int128>(p[i + 1].x - p[0].x) * (p[i].y - p[0].y);
  }
  return Abs128(sum);
}

// Sutherland-Hodgman: the leaf's polygon clipped by each emitter edge.
int64_t Clipper::LeafFractionQ32(uint32_t leaf) const {
  Point2 poly[kMaxClipped], next[kMaxClipped];
  int n = h->node_corner_count[leaf];
  for (int k = 0; k < n; ++k) poly[k] = Corner32(leaf, k);
  const Int128 leaf_area = TwiceArea(poly, n);
  for (int e = 0; e < count && n > 0; ++e) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const Point2 s = poly[(i + n - 1) % n], p = poly[i];
      const Int128 ds = Side(e, s), dp = Side(e, p);
      if ((ds < 0) != (dp < 0)) {
        const Int128 t = (ds * (static_cast<Int128>(1) << kCrossingFracBits)) / (ds - dp);
        const Int128 half = static_cast<Int128>(1) << (kCrossingFracBits - 1);
        next[m++] = {s.x + static_cast<int64_t>(((p.x - s.x) * t + half) >> kCrossingFracBits),
                     s.y + static_cast<int64_t>(((p.y - s.y) * t + half) >> kCrossingFracBits)};
      }
      if (dp >= 0) next[m++] = p;
    }
    for (int i = 0; i < m; ++i) poly[i] = next[i];
    n = m;
  }
  if (n < 3 || leaf_area == 0) return 0;
  Int128 covered = TwiceArea(poly, n), whole = leaf_area;
  while (covered >= (static_cast<Int128>(1) << 94)) {
    covered >>= 1;
    whole >>= 1;
  }
  const Int128 f = (covered * (static_cast<Int128>(1) << kCoverageFracBits) + whole / 2) / whole;
  const int64_t one = int64_t{1} << kCoverageFracBits;
  return f > one ? one : static_cast<int64_t>(f);
}

void Clipper::Cover(uint32_t node, int64_t* out) {
  const int kind = Classify(node);
  if (kind == 0) return;
  if (kind == 2) return CoverAll(node, out);
  if (h->leaf(node)) {
    const int64_t f = LeafFractionQ32(node);
    if (f > 0) {
      out[node] = f;
      any = true;
    }
    return;
  }
  const uint32_t first = h->node_first_child[node];
  for (uint32_t c = first; c < first + h->node_child_count[node]; ++c) Cover(c, out);
}

Status Invalid(const char* why) {
  return Status(StatusCode::kInvalidArgument, std::string("surface emitter: ") + why);
}

}  // namespace

Status SurfaceEmitterCoverageQ32(const BakeHierarchy& hierarchy, const BakeMesh& mesh,
                                 uint32_t root, const int32_t (*corners_q16)[3], int corner_count,
                                 int64_t* leaf_fraction_q32) {
  if (corner_count < kMinSurfaceEmitterCorners || corner_count > kMaxSurfaceEmitterCorners) {
    return Invalid("needs 3 to 8 corners");
  }
  const int32_t* c0 = &mesh.positions[3 * size_t{hierarchy.node_corners[size_t{root} * kBakeMaxNodeCorners]}];
  Int128 normal[3];
  NodeNormalQ32(hierarchy, mesh, root, normal);
  int drop = 0;
  for (int i = 1; i < 3; ++i)
    if (Abs128(normal[i]) > Abs128(normal[drop])) drop = i;
  if (normal[drop] == 0) return Invalid("surface has no area");
  // Plane distance: n scaled below 2^40 so n.n and the dot products fit.
  int64_t n40[3];
  Int128 big = Abs128(normal[drop]);
  int shift = 0;
  while ((big >> shift) >= (static_cast<Int128>(1) << 40)) ++shift;
  for (int i = 0; i < 3; ++i) n40[i] = static_cast<int64_t>(normal[i] >> shift);
  const uint64_t length = ISqrt128(static_cast<UInt128>(static_cast<Int128>(n40[0]) * n40[0] +
                                                        static_cast<Int128>(n40[1]) * n40[1] +
                                                        static_cast<Int128>(n40[2]) * n40[2]));
  for (int k = 0; k < corner_count; ++k) {
    Int128 dot = 0;
    for (int i = 0; i < 3; ++i) dot += static_cast<Int128>(int64_t{corners_q16[k][i]} - c0[i]) * n40[i];
    if (Abs128(dot) > static_cast<Int128>(kSurfaceEmitterPlaneToleranceQ16) * length) {
      return Invalid("a corner lies more than 2 mm off the surface's plane");
    }
  }
  Clipper clip;
  clip.h = &hierarchy;
  clip.mesh = &mesh;
  clip.axis_a = (drop + 1) % 3;
  clip.axis_b = (drop + 2) % 3;
  clip.count = corner_count;
  for (int k = 0; k < corner_count; ++k) {
    clip.emitter[k] = {corners_q16[k][clip.axis_a], corners_q16[k][clip.axis_b]};
  }
  // Strictly convex: every corner strictly left (or strictly right) of every
  // edge it is not on; this also rejects self-crossing "stars".
  int sign = 0;
  for (int e = 0; e < corner_count; ++e) {
    const Point2 a = clip.emitter[e], b = clip.emitter[(e + 1) % corner_count];
    for (int k = 0; k < corner_count; ++k) {
      if (k == e || k == (e + 1) % corner_count) continue;
      const Point2 p = clip.emitter[k];
      const Int128 side = static_cast<Int128>(b.x - a.x) * (p.y - a.y) -
                          static_cast<Int128>(b.y - a.y) * (p.x - a.x);
      const int s = side > 0 ? 1 : side < 0 ? -1 : 0;
      if (s == 0 || (sign != 0 && s != sign)) {
        return Invalid("the polygon is not strictly convex (corners out of order or in a line)");
      }
      sign = s;
    }
  }
  if (sign < 0) {
    for (int i = 0, j = corner_count - 1; i < j; ++i, --j) {
      const Point2 t = clip.emitter[i];
      clip.emitter[i] = clip.emitter[j];
      clip.emitter[j] = t;
    }
  }
  // Only covered leaves are written, so a polygon that misses the surface
  // leaves the output as it was.
  clip.Cover(root, leaf_fraction_q32);
  if (!clip.any) return Invalid("the polygon does not overlap the surface");
  return Status::Ok();
}

}  // namespace relight
