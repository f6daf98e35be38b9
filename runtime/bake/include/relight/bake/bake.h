// The bake: everything the runtime needs, as the runtime's own integer
// formats. The baker fills a Bake and calls WriteBake(); the runtime calls
// ReadBake() once at start-up (it allocates; nothing after it does).
// The on-disk layout is specified in docs/bake-format.md and bake_format.h.
//
// Receiver sets: set 0 is the mesh's vertices (values in cd/m^2, luminance of
// a diffuse surface); set k >= 1 is calculation grid k-1 (values in lux,
// illuminance on the grid's plane).
//
// Thread safety: a Bake is plain data; ReadBake/WriteBake touch only their
// arguments and may run concurrently on different objects.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "relight/base/fixed.h"
#include "relight/base/status.h"

namespace relight {

// How a luminaire's light is split between the exact run-time direct term and
// the SH basis (DESIGN.md "split direct from indirect").
enum class DirectMode : uint8_t {
  kExactDirect = 0,  // direct evaluated per receiver at run time, SH holds indirect only
  kAllInSh = 1,      // Dobashi's original: SH holds direct + indirect
};

// How the fixture hangs. Beam axis at pan = tilt = 0: down (-z) when hanging,
// up (+z) when standing, horizontal out of the wall (+x before the yaw) on a
// wall. Tilt turns the beam towards +x of the panned frame; pan turns about
// +z, counter-clockwise seen from above:
//   hanging:  axis = (sin t cos p, sin t sin p, -cos t)
//   standing: axis = (sin t cos p, sin t sin p, +cos t)
//   wall:     axis = (cos t, -sin t sin p, -sin t cos p)   (pan about the wall's
//             normal, tilt towards the floor at pan 0)
// then the yaw turns all of it about world +z (counter-clockwise from above).
//
// The fixture frame, in which the photometric angles of a direction are
// measured (photometric type C, as IES and EULUMDAT files define them):
//   axis = gamma 0; c0 = the C 0 direction at gamma 90; c90 = C 90 at gamma 90,
//   with c0 x c90 = -axis (C grows counter-clockwise seen from behind the
//   fixture looking along its beam: from above a hanging one). With
//   ct, st, cp, sp the cos and sin of tilt and pan, before roll and yaw:
//     hanging:  c0 = (ct cp, ct sp, st),   c90 = (-sp, cp, 0)
//     standing: c0 = (ct cp, ct sp, -st),  c90 = (sp, -cp, 0)
//     wall:     the hanging vectors v mapped to (-v.z, -v.y, -v.x)
//   The roll turns c0 towards c90 about the axis (c0' = cos r c0 + sin r c90,
//   c90' = -sin r c0 + cos r c90): the fixture turned in its yoke / on its
//   bracket by r degrees of C. The yaw turns the three about world +z.
//   A direction d has gamma = angle(d, axis) and C = atan2(d.c90, d.c0).
//   The SH coefficients of a LID are taken in the right-handed frame
//   (x, y, z) = (c0, c90, -axis).
enum class Mounting : uint8_t { kHanging = 0, kStanding = 1, kWall = 2 };

struct BakeMesh {
  std::vector<int32_t> positions;   // Q16.16 metres, xyz per vertex
  std::vector<int16_t> normals;     // Q1.14 unit vector per vertex
  std::vector<uint16_t> albedo;     // RGB reflectance rho per vertex, 65535 = 1.0
  std::vector<uint32_t> triangles;  // 3 vertex indices per triangle, CCW from the front
  std::vector<uint32_t> triangle_surface;  // input surface index per triangle (picking)
  std::vector<std::string> surface_names;  // per input surface
  uint32_t vertex_count() const { return static_cast<uint32_t>(positions.size() / 3); }
  uint32_t triangle_count() const { return static_cast<uint32_t>(triangles.size() / 3); }
};

struct BakeGrid {
  std::string name;
  uint32_t columns = 0, rows = 0;  // rows * columns == point count for a rectangle; 0, 0 for a list
  std::vector<int32_t> points;     // Q16.16 metres, xyz per point
  std::vector<int16_t> normals;    // Q1.14 per point
  uint32_t point_count() const { return static_cast<uint32_t>(points.size() / 3); }
};

// A luminous intensity distribution. `candela` is the rotationally symmetric
// part, sampled at uniform gamma steps from 0 to 180 degrees inclusive: the
// whole LID of an axisymmetric luminaire (Legendre weights, Dobashi Eq. 19,
// and the exact direct term by gamma alone). A luminaire that is not
// axisymmetric (a photometric file with C planes) also has its full table
// over (C, gamma) in the fixture frame (see Mounting), with the file's
// symmetry expanded to the full circle and its own angles, which the exact
// direct term interpolates bilinearly; and the real-SH coefficients of that
// table in the fixture frame, which the runtime rotates to the aim (then
// `candela` is the average over C, kept for display and edits).
struct BakeLid {
  std::vector<int64_t> candela;  // Q48.16 cd, sample k at gamma = 180 * k / (n - 1) degrees
  std::vector<int32_t> c_deg;      // Q16.16 degrees: 0 first, 360 last, strictly increasing
  std::vector<int32_t> gamma_deg;  // Q16.16 degrees: strictly increasing within [0, 180]
  std::vector<int64_t> table;      // Q48.16 cd, [plane * gammas + g]; plane at 360 = plane at 0
  std::vector<int64_t> sh;         // Q48.16 cd, (N+1)^2 coefficients, ShIndex order
  bool axisymmetric() const { return c_deg.empty(); }
};

// A zoom optic (a scene LID of type "beam" with a zoom range,
// docs/scene-format.md): the beam keeps the shape of one normalised profile
// f(x), x = gamma / (beam angle / 2), f(0) = 1, f(1) = 1/2, 0 past the last
// sample, while its beam angle moves within [min, max] and its lumens stay
// as they are (a zoom optic moves the light, it does not make more). The
// engine turns a beam angle into the LID samples peak x f(gamma / half
// angle), with the peak that keeps the lumens (Engine::SetZoom). An empty
// profile: the luminaire has no zoom (the file holds no zoom before version 4).
struct BakeZoom {
  int32_t min_deg = 0;      // Q16.16 degrees, full beam angle at half peak, in (0, 180)
  int32_t max_deg = 0;      // Q16.16 degrees, in [min, 180)
  int32_t default_deg = 0;  // Q16.16 degrees in [min, max]: the angle of BakeLid::candela
  int64_t lumens = 0;       // Q48.16 lm, held as the beam zooms
  int32_t profile_end = 0;  // Q16.16: the x of the last profile sample
  std::vector<int32_t> profile;  // Q2.30, f at x = profile_end * k / (F - 1); f(0) = 2^30
  bool present() const { return !profile.empty(); }
};

// Clustered principal components of one basis (Sloan et al. 2003, "Clustered
// principal components for precomputed radiance transfer"), held instead of
// BakeLightReceivers::basis (format version 5 on, section CPCA). Each
// receiver's 3 x (N+1)^2 basis values are its cluster's mean plus a weighted
// sum of r component vectors. Clusters are runs of consecutive receivers.
//   vectors: per (term, channel) one row of cluster_count * (r + 1) values,
//     term-major like `basis`: vectors[(t * V + c * (r + 1) + j) * 3 + ch]
//     with V = cluster_count * (r + 1); j = 0 is cluster c's mean, j >= 1 its
//     component j - 1, scaled so that a weight of 1 is the largest any of the
//     cluster's receivers has; real = q * vector_scale[t * 3 + ch].
//   weights: cluster by cluster, component-major inside a cluster: receiver
//     cluster_start[c] + i has weight j at weights[cluster_start[c] * r + j * n_c + i]
//     (n_c its cluster's size); real weight = q / kCompressedWeightOne.
//     That is the file's order. The engine reorders them at Open into tiles
//     of 16 receivers (CompressedWeightOrder::kTiles16, engine
//     compressed_tiles.h), so its kernel reads one sequential stream.
// The runtime recombines this form without expanding it (engine, compressed_recombine.h).
inline constexpr int16_t kCompressedWeightOne = 16383;
// A basis may hold its weights in 8 bits (weight_bits = 8, section CPC8,
// format version 8): a weight of 1 is then 127.
inline constexpr int16_t kCompressedWeightOne8 = 127;
inline constexpr int32_t CompressedWeightOne(uint8_t weight_bits) {
  return weight_bits == 8 ? kCompressedWeightOne8 : kCompressedWeightOne;
}
inline constexpr uint32_t kMaxCompressedComponents = 64;

enum class CompressedWeightOrder : uint8_t {
  kComponentMajor,  // as in the file (above); what the baker builds and the writer takes
  kTiles16,         // the engine's run-time order; never written
};

struct BakeCompressedBasis {
  uint32_t components = 0;               // r, in [0, kMaxCompressedComponents]
  std::vector<uint32_t> cluster_start;   // C + 1: 0 first, the receiver count last, increasing
  std::vector<int16_t> vectors;          // 3 x terms x C x (r + 1), see above
  std::vector<QuantScale> vector_scale;  // [term][channel]
  std::vector<int16_t> weights;          // receivers x r, each in [-one, one], one = CompressedWeightOne(weight_bits)
  CompressedWeightOrder weight_order = CompressedWeightOrder::kComponentMajor;
  uint8_t weight_bits = 16;              // 16, or 8: weights in [-127, 127]
  // The engine's 8-bit tiles (weight_bits 8 and kTiles16 only; `weights` is
  // then empty): the same order, a byte a weight.
  std::vector<int8_t> weights8;
  bool present() const { return !cluster_start.empty(); }
  uint32_t cluster_count() const {
    return cluster_start.empty() ? 0 : static_cast<uint32_t>(cluster_start.size() - 1);
  }
  // Bytes of the arrays in the engine's memory (8-bit weights a byte each,
  // as the engine holds them, whichever vector carries them now).
  uint64_t memory_bytes() const {
    return 4 * uint64_t{cluster_start.size()} + 2 * uint64_t{vectors.size()} +
           8 * uint64_t{vector_scale.size()} + (weight_bits == 8 ? 1 : 2) * uint64_t{weights.size()} +
           uint64_t{weights8.size()};
  }
};

// Per luminaire and receiver set.
struct BakeLightReceivers {
  // Exact direct term (empty in DirectMode::kAllInSh).
  std::vector<int16_t> direction;  // Q1.14 unit vector luminaire -> receiver, world frame
  std::vector<uint32_t> geometry;  // visibility * cos(receiver) / d^2, real = q * geometry_scale
  QuantScale geometry_scale;       // m^-2 per LSB
  // SH basis, term-major: basis[(t * count + r) * 3 + c], real = q * basis_scale[t * 3 + c].
  // Units per candela of Y_t: cd/m^2 (vertices) or lux (grids).
  std::vector<int16_t> basis;
  std::vector<QuantScale> basis_scale;  // [term][channel]
  // When present, the basis in compressed form; `basis` and `basis_scale` are then empty.
  BakeCompressedBasis compressed;
};

struct BakeLuminaire {
  std::string name;
  int32_t position[3] = {0, 0, 0};  // Q16.16 metres
  Mounting mounting = Mounting::kHanging;
  DirectMode direct_mode = DirectMode::kExactDirect;
  uint8_t sh_degree = 0;             // N; (N+1)^2 terms
  uint8_t use_sigma = 1;             // damp the Legendre series with sigma(N, l) (Dobashi Eq. 12-13)
  int32_t default_pan = 0;           // Q16.16 degrees
  int32_t default_tilt = 0;          // Q16.16 degrees
  int32_t yaw = 0;                   // Q16.16 degrees, turn of the base about world +z
  int32_t roll = 0;                  // Q16.16 degrees, default roll about the beam axis
  // Console ranges (Q16.16 degrees): a 16-bit pan or tilt value v means
  // (v - 32768) / 65536 x range, so 32768 is home (0) and the range is centred.
  int32_t pan_range = 540 << 16;
  int32_t tilt_range = 270 << 16;
  int16_t default_dimmer = 32767;    // Q1.15
  int16_t default_rgb[3] = {32767, 32767, 32767};  // Q1.15
  BakeLid lid;
  BakeZoom zoom;                              // version 4 on; absent before
  std::vector<BakeLightReceivers> receivers;  // [receiver set]: vertices, then each grid
};

struct BakeCamera {
  int32_t position[3] = {0, 0, 0};  // Q16.16 metres
  int32_t target[3] = {0, 0, 0};    // Q16.16 metres
  int32_t fov_y = 50 << 16;         // Q16.16 degrees, vertical
};

// Hierarchical radiosity's quadtrees and links (docs/hierarchy.md), kept so
// that light sources placed on surfaces at run time (Chandran & Srivastava's
// fractional emissivity) can re-solve radiosity from the bake alone. Plain
// integer arrays, one entry per node (node_*) or per link (link_*).
inline constexpr uint32_t kBakeNoIndex = 0xFFFFFFFFu;
inline constexpr int kBakeMaxNodeCorners = 6;
// Link gradients: int32 with this many fraction bits, per metre (Q8.23).
inline constexpr int kBakeGradientFracBits = 23;

struct BakeHierarchy {
  // Nodes, surface by surface in surface order; within a surface breadth
  // first from its root (parents before children, each node's children
  // contiguous). Every surface with triangles has one tree; its leaves cover
  // each of its triangles exactly once.
  std::vector<uint16_t> node_surface;
  std::vector<uint32_t> node_parent;       // kBakeNoIndex for a root
  std::vector<uint32_t> node_first_child;  // kBakeNoIndex for a leaf
  std::vector<uint8_t> node_child_count;   // 0 for a leaf, else >= 2
  std::vector<uint8_t> node_corner_count;  // 3 .. kBakeMaxNodeCorners
  // kBakeMaxNodeCorners per node: mesh vertex indices of the convex polygon,
  // CCW from the lit side; unused slots kBakeNoIndex.
  std::vector<uint32_t> node_corners;
  // Q32.32 m^2: a leaf's patch area (> 0), an inner node's exactly the sum of its children's.
  std::vector<uint64_t> node_area;
  // Leaves: the first of their corner_count - 2 render triangles, a fan from
  // corner 0 (corners 0, k+1, k+2). kBakeNoIndex for an inner node.
  std::vector<uint32_t> node_leaf_triangle;

  // Links, sorted by (p, q) with p < q, between nodes on different surfaces.
  // f_pq: mean irradiance on p (lux) per unit exitance of q (lm/m^2), i.e. the
  // form factor with visibility, UQ0.32; f_qp the reverse. g_pq: how that
  // irradiance varies over p, (d/du, d/dv) per metre in p's surface frame
  // about p's area centroid, kBakeGradientFracBits fraction bits; 0 for a leaf
  // p and wherever f_pq is 0. The frame: u = unit(root corner 1 - root corner
  // 0), v = n x u, n the surface's normal.
  std::vector<uint32_t> link_p, link_q;
  std::vector<uint32_t> link_f_pq, link_f_qp;
  std::vector<int32_t> link_g_pq, link_g_qp;  // 2 per link: u, v

  // Links from the nodes to the calculation grids' points (format version 6,
  // section GLNK), so run-time emitters light the grids. Points are numbered
  // across the grids in grid order. Point i gathers from grid_link_node[e]
  // with factor grid_link_f[e] for e in [grid_link_offsets[i],
  // grid_link_offsets[i + 1]): the irradiance at the point (lux) per unit
  // exitance of the node (lm/m^2), with visibility, UQ0.32; nodes ascending
  // within a point. Empty (no offsets): the bake has none (older bakes).
  std::vector<uint32_t> grid_link_offsets;  // total grid points + 1, or empty
  std::vector<uint32_t> grid_link_node, grid_link_f;

  uint32_t node_count() const { return static_cast<uint32_t>(node_surface.size()); }
  uint32_t link_count() const { return static_cast<uint32_t>(link_p.size()); }
  bool has_grid_links() const { return !grid_link_offsets.empty(); }
  bool leaf(uint32_t node) const { return node_child_count[node] == 0; }
};

struct Bake {
  std::string scene_name;
  BakeMesh mesh;
  std::vector<BakeGrid> grids;
  std::vector<BakeLuminaire> luminaires;
  BakeCamera camera;
  // LightQ12 cd/m^2 shown as diffuse white (sRGB 193, about 53% linear); the
  // tone map rolls highlights off up to 4x this, where it reaches 255.
  int32_t white_luminance = 100 << kLightFracBits;
  // Only bakes of the hierarchical solver have one (sections HIER and LINK).
  std::optional<BakeHierarchy> hierarchy;

  uint32_t receiver_set_count() const { return 1 + static_cast<uint32_t>(grids.size()); }
  uint32_t receiver_count(uint32_t set) const {
    return set == 0 ? mesh.vertex_count() : grids[set - 1].point_count();
  }
};

// One section of a written file, for size reports.
struct BakeSectionSize {
  char tag[5] = {};  // "META", "MESH", ..., "HIER", "LINK"
  uint64_t raw_bytes = 0, stored_bytes = 0;
};

// Writes atomically: a temporary file beside `path`, fsync, rename. On any
// error the previous file at `path` (if any) is untouched. The file has
// format version 4 when a luminaire has a zoom, else 3 when it holds a
// hierarchy, else 2 (the lowest that holds it, so older readers read it);
// 5 when a basis is compressed (section CPCA); 6 when the hierarchy has
// grid links (section GLNK).
// `sizes`, if given, receives every section's raw and stored size, in file order.
// Returns kOk, kInvalidArgument (inconsistent sizes, named), kIoError.
Status WriteBake(const Bake& bake, const std::string& path,
                 std::vector<BakeSectionSize>* sizes = nullptr);

// Checks a Bake in memory against every rule ReadBake enforces on a file
// (bake_check.h, limits in bake_limits.h): WriteBake and Engine::Open run it.
// Returns kOk or kInvalidArgument ("bake: <part>: <what and where>").
// Thread-safe (reads its argument only).
Status ValidateBake(const Bake& bake);

// Reads and fully validates a bake: sizes, checksums, counts, index ranges,
// degrees, scales. Returns kOk, kNotFound, kIoError, kCorrupt (what and
// where), kUnsupported (newer version). `out` is only written on success.
Status ReadBake(const std::string& path, Bake* out);
struct ReadBakeOptions {
  // false: the hierarchy's sections (HIER, LINK, GLNK) are skipped, neither
  // decompressed nor kept (Bake::hierarchy stays empty), for a reader that
  // places no light sources on surfaces: they are most of a hierarchical
  // bake's memory once read. Everything else is read and checked as always.
  bool hierarchy = true;
  // false: the bake is read as if it had no calculation grid (Bake::grids
  // empty, one receiver set per luminaire, no GLNK): the grids' bases and
  // direct terms are skipped, neither decompressed nor kept, for a reader
  // that shows surfaces only. Their sizes are still checked.
  bool grids = true;
};
Status ReadBake(const std::string& path, const ReadBakeOptions& options, Bake* out);
// Same, from bytes in memory (used by tests and fuzzing).
Status ParseBake(const uint8_t* data, size_t size, Bake* out);

}  // namespace relight
