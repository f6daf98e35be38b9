// A small but complete Bake from a fixed seed (every kind of section, both
// direct modes, a rectangle and a list grid, a zero-scale block, an
// unreachable receiver, a radiosity hierarchy), and a field-by-field
// comparison of two bakes.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/base/sh_index.h"

namespace relight::bake_test {

// --- A small but complete bake from a fixed seed.
inline int16_t Q14(double v) { return static_cast<int16_t>(std::lround(v * 16384.0)); }

inline void PutUnit(std::mt19937* rng, std::vector<int16_t>* out) {
  std::normal_distribution<double> n(0, 1);
  double x = n(*rng), y = n(*rng), z = n(*rng);
  const double len = std::sqrt(x * x + y * y + z * z);
  out->push_back(Q14(x / len));
  out->push_back(Q14(y / len));
  out->push_back(Q14(z / len));
}

inline QuantScale RandomScale(std::mt19937* rng) {
  std::uniform_int_distribution<int32_t> m(1 << 29, (1 << 30) - 1), e(-40, 8);
  return QuantScale{m(*rng), e(*rng)};
}

template <typename T>
T RandomInt(std::mt19937* rng, int64_t lo, int64_t hi) {
  return static_cast<T>(std::uniform_int_distribution<int64_t>(lo, hi)(*rng));
}

inline BakeLightReceivers MakeReceivers(std::mt19937* rng, const BakeLuminaire& lum,
                                        uint32_t count) {
  BakeLightReceivers r;
  if (lum.direct_mode == DirectMode::kExactDirect) {
    for (uint32_t i = 0; i < count; ++i) {
      PutUnit(rng, &r.direction);
      r.geometry.push_back(RandomInt<uint32_t>(rng, 0, UINT32_MAX));
    }
    if (count > 1) {  // a receiver the luminaire cannot reach: no direction
      r.geometry[1] = 0;
      r.direction[3] = r.direction[4] = r.direction[5] = 0;
    }
    r.geometry_scale = RandomScale(rng);
  }
  const size_t terms = static_cast<size_t>(ShTermCount(lum.sh_degree));
  for (size_t i = 0; i < terms * count * 3; ++i) {
    r.basis.push_back(RandomInt<int16_t>(rng, -32767, 32767));
  }
  for (size_t i = 0; i < terms * 3; ++i) r.basis_scale.push_back(RandomScale(rng));
  // Term 1, blue: an all-zero block has the zero scale.
  r.basis_scale[1 * 3 + 2] = QuantScale{};
  for (uint32_t i = 0; i < count; ++i) r.basis[(1 * count + i) * 3 + 2] = 0;
  return r;
}

inline BakeLuminaire MakeLuminaire(std::mt19937* rng, const char* name, DirectMode mode, int degree,
                                   size_t lid_samples) {
  BakeLuminaire lum;
  lum.name = name;
  for (int32_t& v : lum.position) v = RandomInt<int32_t>(rng, -(5 << 16), 5 << 16);
  lum.mounting = mode == DirectMode::kExactDirect ? Mounting::kHanging : Mounting::kStanding;
  lum.direct_mode = mode;
  lum.sh_degree = static_cast<uint8_t>(degree);
  lum.use_sigma = mode == DirectMode::kExactDirect ? 1 : 0;
  lum.default_pan = RandomInt<int32_t>(rng, -(270 << 16), 270 << 16);
  lum.default_tilt = RandomInt<int32_t>(rng, -(135 << 16), 135 << 16);
  lum.default_dimmer = RandomInt<int16_t>(rng, 0, 32767);
  for (int16_t& v : lum.default_rgb) v = RandomInt<int16_t>(rng, 0, 32767);
  for (size_t k = 0; k < lid_samples; ++k) {
    lum.lid.candela.push_back(RandomInt<int64_t>(rng, 0, int64_t{20000} << 16));
  }
  return lum;
}

// A (C, gamma) table with its SH coefficients (format version 2): planes
// 0, 90, 200, 360 and gammas 0..180 in 30-degree steps, random values.
inline void MakeLidTable(std::mt19937* rng, BakeLuminaire* lum) {
  lum->lid.c_deg = {0, 90 << 16, 200 << 16, 360 << 16};
  for (int g = 0; g <= 180; g += 30) lum->lid.gamma_deg.push_back(g << 16);
  const size_t gammas = lum->lid.gamma_deg.size();
  for (size_t p = 0; p < 3; ++p) {
    for (size_t g = 0; g < gammas; ++g) {
      lum->lid.table.push_back(RandomInt<int64_t>(rng, 0, int64_t{5000} << 16));
    }
  }
  for (size_t g = 0; g < gammas; ++g) lum->lid.table.push_back(lum->lid.table[g]);
  for (int t = 0; t < ShTermCount(lum->sh_degree); ++t) {
    lum->lid.sh.push_back(RandomInt<int64_t>(rng, -(int64_t{3000} << 16), int64_t{3000} << 16));
  }
  lum->yaw = RandomInt<int32_t>(rng, -(360 << 16), 360 << 16);
  lum->roll = RandomInt<int32_t>(rng, -(360 << 16), 360 << 16);
  lum->pan_range = 630 << 16;
  lum->tilt_range = 265 << 16;
}

// A hierarchy over the test bake's 11 vertices and 8 triangles (format
// version 3), replacing its random triangles with the leaves' fans:
//   surface 0: node 0 (root, 4 corners) -> 1 (quad leaf: triangles 0, 1) and
//              2 (5 corners) -> 3, 4, 5 (triangle leaves: 2, 3, 4)
//   surface 1: node 6, a quad root that is a leaf (triangles 5, 6)
//   surface 2: node 7, a triangle root that is a leaf (triangle 7)
// and links between them: inner receivers with gradients, a zero factor.
inline void AddHierarchy(uint32_t seed, Bake* b) {
  std::mt19937 rng(seed + 1000);
  constexpr uint32_t kNo = kBakeNoIndex;
  struct Node {
    uint16_t surface;
    uint32_t parent, first_child;
    uint8_t child_count;
    std::vector<uint32_t> corners;
    uint32_t leaf_triangle;
  };
  const Node nodes[] = {{0, kNo, 1, 2, {0, 4, 5, 3}, kNo},       {0, 0, kNo, 0, {0, 1, 2, 3}, 0},
                        {0, 0, 3, 3, {1, 4, 5, 3, 2}, kNo},      {0, 2, kNo, 0, {1, 4, 2}, 2},
                        {0, 2, kNo, 0, {4, 5, 2}, 3},            {0, 2, kNo, 0, {2, 5, 3}, 4},
                        {1, kNo, kNo, 0, {6, 7, 8, 9}, 5},       {2, kNo, kNo, 0, {7, 10, 8}, 7}};
  BakeHierarchy h;
  b->mesh.triangles.clear();
  b->mesh.triangle_surface.clear();
  for (const Node& n : nodes) {
    h.node_surface.push_back(n.surface);
    h.node_parent.push_back(n.parent);
    h.node_first_child.push_back(n.first_child);
    h.node_child_count.push_back(n.child_count);
    h.node_corner_count.push_back(static_cast<uint8_t>(n.corners.size()));
    for (int k = 0; k < kBakeMaxNodeCorners; ++k) {
      h.node_corners.push_back(k < static_cast<int>(n.corners.size()) ? n.corners[k] : kNo);
    }
    h.node_leaf_triangle.push_back(n.leaf_triangle);
    h.node_area.push_back(n.child_count == 0 ? RandomInt<uint64_t>(&rng, 1, uint64_t{1} << 36) : 0);
    if (n.child_count != 0) continue;
    for (size_t k = 1; k + 1 < n.corners.size(); ++k) {  // the leaf's fan
      b->mesh.triangles.insert(b->mesh.triangles.end(),
                               {n.corners[0], n.corners[k], n.corners[k + 1]});
      b->mesh.triangle_surface.push_back(n.surface);
    }
  }
  h.node_area[2] = h.node_area[3] + h.node_area[4] + h.node_area[5];
  h.node_area[0] = h.node_area[1] + h.node_area[2];
  // (p, q, f_pq zero?): nodes 0 and 2 are inner, so they receive gradients.
  const std::pair<uint32_t, uint32_t> pairs[] = {{0, 6}, {0, 7}, {1, 6}, {2, 6},
                                                 {2, 7}, {3, 7}, {5, 6}};
  for (const auto& [p, q] : pairs) {
    h.link_p.push_back(p);
    h.link_q.push_back(q);
    const bool zero_pq = p == 2 && q == 7;
    // At most 1/8 each: what a node and its ancestors gather sums to <= 1
    // (bake_check_hierarchy.cc); node 6 gathers from 4 links.
    h.link_f_pq.push_back(zero_pq ? 0 : RandomInt<uint32_t>(&rng, 1, UINT32_MAX / 8));
    h.link_f_qp.push_back(RandomInt<uint32_t>(&rng, 1, UINT32_MAX / 8));
    for (int a = 0; a < 2; ++a) {
      const bool inner_p = h.node_child_count[p] != 0 && !zero_pq;
      h.link_g_pq.push_back(inner_p ? RandomInt<int32_t>(&rng, INT32_MIN, INT32_MAX) : 0);
      h.link_g_qp.push_back(0);  // nodes 6 and 7 are leaves
    }
  }
  b->hierarchy = std::move(h);
}

inline Bake MakeBake(uint32_t seed) {
  std::mt19937 rng(seed);
  Bake b;
  b.scene_name = "test room";
  b.white_luminance = 150 << 12;
  b.camera.position[0] = 1 << 16;
  b.camera.position[2] = 3 << 16;
  b.camera.target[1] = -(2 << 16);
  b.camera.fov_y = 60 << 16;
  const uint32_t vertices = 11;
  for (uint32_t v = 0; v < vertices; ++v) {
    for (int a = 0; a < 3; ++a) {
      b.mesh.positions.push_back(RandomInt<int32_t>(&rng, -(5 << 16), 5 << 16));
    }
    PutUnit(&rng, &b.mesh.normals);
    for (int c = 0; c < 3; ++c) b.mesh.albedo.push_back(RandomInt<uint16_t>(&rng, 0, 65535));
  }
  b.mesh.surface_names = {"floor", "wall north", "B\xC3\xBChne"};  // UTF-8 is allowed
  for (int t = 0; t < 8; ++t) {
    for (int k = 0; k < 3; ++k) {
      b.mesh.triangles.push_back(RandomInt<uint32_t>(&rng, 0, vertices - 1));
    }
    b.mesh.triangle_surface.push_back(RandomInt<uint32_t>(&rng, 0, 2));
  }
  BakeGrid desk;
  desk.name = "desk";
  desk.columns = 4;
  desk.rows = 3;
  BakeGrid path;
  path.name = "path";  // a list: 0 x 0
  for (BakeGrid* g : {&desk, &path}) {
    const int points = g == &desk ? 12 : 5;
    for (int p = 0; p < points; ++p) {
      for (int a = 0; a < 3; ++a) {
        g->points.push_back(RandomInt<int32_t>(&rng, -(5 << 16), 5 << 16));
      }
      PutUnit(&rng, &g->normals);
    }
  }
  b.grids = {desk, path};
  b.luminaires.push_back(MakeLuminaire(&rng, "spot", DirectMode::kExactDirect, 2, 181));
  b.luminaires.push_back(MakeLuminaire(&rng, "wash", DirectMode::kAllInSh, 3, 37));
  MakeLidTable(&rng, &b.luminaires[0]);
  b.luminaires[1].mounting = Mounting::kWall;
  for (BakeLuminaire& lum : b.luminaires) {
    for (uint32_t s = 0; s < b.receiver_set_count(); ++s) {
      lum.receivers.push_back(MakeReceivers(&rng, lum, b.receiver_count(s)));
    }
  }
  AddHierarchy(seed, &b);
  return b;
}

inline bool ScalesEqual(const std::vector<QuantScale>& a, const std::vector<QuantScale>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].mantissa != b[i].mantissa || a[i].exponent != b[i].exponent) return false;
  }
  return true;
}

inline void ExpectHierarchiesEqual(const std::optional<BakeHierarchy>& a,
                                   const std::optional<BakeHierarchy>& b) {
  ASSERT_EQ(a.has_value(), b.has_value());
  if (!a) return;
  EXPECT_EQ(a->node_surface, b->node_surface);
  EXPECT_EQ(a->node_parent, b->node_parent);
  EXPECT_EQ(a->node_first_child, b->node_first_child);
  EXPECT_EQ(a->node_child_count, b->node_child_count);
  EXPECT_EQ(a->node_corner_count, b->node_corner_count);
  EXPECT_EQ(a->node_corners, b->node_corners);
  EXPECT_EQ(a->node_area, b->node_area);
  EXPECT_EQ(a->node_leaf_triangle, b->node_leaf_triangle);
  EXPECT_EQ(a->link_p, b->link_p);
  EXPECT_EQ(a->link_q, b->link_q);
  EXPECT_EQ(a->link_f_pq, b->link_f_pq);
  EXPECT_EQ(a->link_f_qp, b->link_f_qp);
  EXPECT_EQ(a->link_g_pq, b->link_g_pq);
  EXPECT_EQ(a->link_g_qp, b->link_g_qp);
  EXPECT_EQ(a->grid_link_offsets, b->grid_link_offsets);
  EXPECT_EQ(a->grid_link_node, b->grid_link_node);
  EXPECT_EQ(a->grid_link_f, b->grid_link_f);
}

inline void ExpectBakesEqual(const Bake& a, const Bake& b) {
  EXPECT_EQ(a.scene_name, b.scene_name);
  EXPECT_EQ(a.white_luminance, b.white_luminance);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(a.camera.position[i], b.camera.position[i]);
    EXPECT_EQ(a.camera.target[i], b.camera.target[i]);
  }
  EXPECT_EQ(a.camera.fov_y, b.camera.fov_y);
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);
  EXPECT_EQ(a.mesh.normals, b.mesh.normals);
  EXPECT_EQ(a.mesh.albedo, b.mesh.albedo);
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
  EXPECT_EQ(a.mesh.triangle_surface, b.mesh.triangle_surface);
  EXPECT_EQ(a.mesh.surface_names, b.mesh.surface_names);
  ASSERT_EQ(a.grids.size(), b.grids.size());
  for (size_t g = 0; g < a.grids.size(); ++g) {
    SCOPED_TRACE("grid " + std::to_string(g));
    EXPECT_EQ(a.grids[g].name, b.grids[g].name);
    EXPECT_EQ(a.grids[g].columns, b.grids[g].columns);
    EXPECT_EQ(a.grids[g].rows, b.grids[g].rows);
    EXPECT_EQ(a.grids[g].points, b.grids[g].points);
    EXPECT_EQ(a.grids[g].normals, b.grids[g].normals);
  }
  ASSERT_EQ(a.luminaires.size(), b.luminaires.size());
  for (size_t l = 0; l < a.luminaires.size(); ++l) {
    SCOPED_TRACE("luminaire " + std::to_string(l));
    const BakeLuminaire& x = a.luminaires[l];
    const BakeLuminaire& y = b.luminaires[l];
    EXPECT_EQ(x.name, y.name);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(x.position[i], y.position[i]);
      EXPECT_EQ(x.default_rgb[i], y.default_rgb[i]);
    }
    EXPECT_EQ(x.mounting, y.mounting);
    EXPECT_EQ(x.direct_mode, y.direct_mode);
    EXPECT_EQ(x.sh_degree, y.sh_degree);
    EXPECT_EQ(x.use_sigma, y.use_sigma);
    EXPECT_EQ(x.default_pan, y.default_pan);
    EXPECT_EQ(x.default_tilt, y.default_tilt);
    EXPECT_EQ(x.default_dimmer, y.default_dimmer);
    EXPECT_EQ(x.lid.candela, y.lid.candela);
    EXPECT_EQ(x.lid.c_deg, y.lid.c_deg);
    EXPECT_EQ(x.lid.gamma_deg, y.lid.gamma_deg);
    EXPECT_EQ(x.lid.table, y.lid.table);
    EXPECT_EQ(x.lid.sh, y.lid.sh);
    EXPECT_EQ(x.yaw, y.yaw);
    EXPECT_EQ(x.roll, y.roll);
    EXPECT_EQ(x.pan_range, y.pan_range);
    EXPECT_EQ(x.tilt_range, y.tilt_range);
    EXPECT_EQ(x.zoom.min_deg, y.zoom.min_deg);
    EXPECT_EQ(x.zoom.max_deg, y.zoom.max_deg);
    EXPECT_EQ(x.zoom.default_deg, y.zoom.default_deg);
    EXPECT_EQ(x.zoom.lumens, y.zoom.lumens);
    EXPECT_EQ(x.zoom.profile_end, y.zoom.profile_end);
    EXPECT_EQ(x.zoom.profile, y.zoom.profile);
    ASSERT_EQ(x.receivers.size(), y.receivers.size());
    for (size_t s = 0; s < x.receivers.size(); ++s) {
      SCOPED_TRACE("receiver set " + std::to_string(s));
      const BakeLightReceivers& p = x.receivers[s];
      const BakeLightReceivers& q = y.receivers[s];
      EXPECT_EQ(p.direction, q.direction);
      EXPECT_EQ(p.geometry, q.geometry);
      EXPECT_TRUE(ScalesEqual({p.geometry_scale}, {q.geometry_scale}));
      EXPECT_EQ(p.basis, q.basis);
      EXPECT_TRUE(ScalesEqual(p.basis_scale, q.basis_scale));
      EXPECT_EQ(p.compressed.components, q.compressed.components);
      EXPECT_EQ(p.compressed.cluster_start, q.compressed.cluster_start);
      EXPECT_EQ(p.compressed.vectors, q.compressed.vectors);
      EXPECT_TRUE(ScalesEqual(p.compressed.vector_scale, q.compressed.vector_scale));
      EXPECT_EQ(p.compressed.weights, q.compressed.weights);
      EXPECT_EQ(p.compressed.weight_bits, q.compressed.weight_bits);
    }
  }
  ExpectHierarchiesEqual(a.hierarchy, b.hierarchy);
}

}  // namespace relight::bake_test
