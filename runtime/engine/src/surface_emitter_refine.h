// Adaptive refine (AR, Chandran & Srivastava Sec. 3.1, Fig. 5): the first
// shot of a run-time emitter from its exact shape instead of from whole
// nodes. Fractional emissivity (FE) lets a partly covered node send its
// covered fraction through every link as if the emitter were spread evenly
// over it; a receiver that sees one corner of the node better than another
// is then lit as if the panel sat in the middle. AR refines every partly
// covered node, down to and below the stored leaves, to the polygon itself:
// the emitting element is the node clipped by the emitter (the limit of
// Fig. 5's Intersection() refined until every element is inside), and each
// of the node's links gets a new factor for it
//
//   f' = f_rs * sum_x F(x -> P n s) / sum_x F(x -> s)
//
// over quadrature points x of the receiver r (point_polygon_factor.h): the
// stored factor keeps its visibility, the ratio of unoccluded factors moves
// the light to where the emitter is. Fully covered nodes send through their
// links unchanged (f' = f). These new links go into a fixed pool sized at
// Open(); a placement that needs more is refused (kOutOfRange) before
// anything changes. The result is the first-shot irradiance per leaf, which
// HierarchySolveQ32 then interreflects.
//
// Open() allocates; FirstShot() is integer-only and allocation-free. Not
// thread-safe (scratch).
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/base/status.h"
#include "relight/engine/surface_emitter.h"

namespace relight {

class SurfaceEmitterRefine {
 public:
  // pool_links: new links one placement may make (kDefaultSurfaceEmitterRefineLinks by default).
  Status Open(const Bake& bake, int pool_links);
  // First-shot irradiance on every leaf, Q32 lux per lm/m^2 the emitter
  // leaves (its surface's unit exitance), from the emitter `shape` on the
  // tree at `root`. coverage_q32 is SurfaceEmitterCoverageQ32's output for
  // the same shape (which also validated it). Writes leaf_irradiance_q32[k]
  // for every node k (inner nodes 0). kOutOfRange, saying how many it needed,
  // when the refinement needs more new links than the pool holds; the output
  // is then untouched.
  Status FirstShot(uint32_t root, const SurfaceEmitterShape& shape, const int64_t* coverage_q32,
                   int64_t* leaf_irradiance_q32);
  // New links the last successful FirstShot made.
  int last_links() const { return last_links_; }
  int pool_links() const { return static_cast<int>(pool_.size()); }

 private:
  // A link the refinement made: irradiance on `receiver` per unit exitance
  // of the emitter (Q32), and its gradient (Q32 per metre, about the
  // receiver's centroid, zero where the receiver was refined).
  struct NewLink {
    uint32_t receiver;
    int64_t e0_q32, eu_q32, ev_q32;
  };
  // The emitting polygon of one source node and its covered fraction.
  struct Source {
    uint32_t node;
    const int64_t (*poly)[3];
    int count;
    uint64_t coverage_q32;
    bool partial;
    int64_t centre[3], radius;  // Bound() of poly
  };
  static void Bound(const int64_t (*poly)[3], int count, int64_t centre[3], int64_t* radius);
  void Send(uint32_t link_side, uint64_t ratio_q32);
  void SendLink(const Source& source, uint32_t link_side);
  void SendSubtree(uint32_t node, int64_t (*scratch)[3]);
  // Sum of F from the receiver's quadrature points to the polygon; with
  // `gradient`, also the least-squares slope of F over them (Q32 per metre).
  // centre, radius: Bound() of the polygon the points are compared with.
  uint64_t SumFactorsQ32(uint32_t receiver, const int64_t (*poly)[3], int count, const int64_t centre[3],
                         int64_t radius, int64_t gradient_q32[2] = nullptr) const;
  bool Far(uint32_t receiver, const int64_t centre[3], int64_t radius) const;
  void RefineReceiver(uint32_t node, const Source& source, uint64_t visibility_q32, uint64_t reverse_q32);
  void Add(uint32_t receiver, int64_t e0, int64_t eu, int64_t ev);
  int Corners(uint32_t node, int64_t (*out)[3]) const;

  const BakeHierarchy* h_ = nullptr;
  const BakeMesh* mesh_ = nullptr;
  std::vector<int64_t> centroid_q16_;     // 3 per node, metres
  std::vector<int64_t> receiver_radius_q16_;  // per node: its corners' largest distance from their centre
  std::vector<int32_t> centre_uv_q16_;    // 2 per node, the gradients' surface frame
  std::vector<int32_t> normal_q30_;       // 3 per surface
  std::vector<int32_t> frame_u_q30_, frame_v_q30_;  // 3 per surface: the gradients' axes
  std::vector<uint8_t> drop_axis_;        // per surface: the normal's largest axis
  std::vector<uint32_t> tree_end_;        // per node that is a root: one past its tree
  std::vector<uint32_t> send_offsets_, send_;  // per source node: link sides it sends through
  std::vector<int64_t> coverage_mean_q32_, e0_, eu_, ev_;
  std::vector<NewLink> pool_;
  uint64_t refine_threshold_q32_ = 0;  // kRefineThresholdQ32
  size_t needed_ = 0;
  int last_links_ = 0;
};

}  // namespace relight
