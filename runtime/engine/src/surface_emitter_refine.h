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
// Open() allocates; FirstShot() is integer-only and allocation-free, and
// spreads the sources' links over the engine's threads when given them. Not
// thread-safe itself (scratch): one caller at a time.
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/base/status.h"
#include "relight/engine/surface_emitter.h"

namespace relight {

class EmitterClip3;
class WorkerPool;

class SurfaceEmitterRefine {
 public:
  // pool_links: new links one placement may make (kDefaultSurfaceEmitterRefineLinks by default);
  // refine_bits: new factors where a link carries 2^-refine_bits of the
  // emitter's exitance or more (0..32, kDefaultSurfaceEmitterRefineBits).
  Status Open(const Bake& bake, int pool_links, int refine_bits = kDefaultSurfaceEmitterRefineBits);
  // First-shot irradiance on every leaf, Q32 lux per lm/m^2 the emitter
  // leaves (its surface's unit exitance), from the emitter `shape` on the
  // tree at `root`. coverage_q32 is SurfaceEmitterCoverageQ32's output for
  // the same shape (which also validated it). Writes leaf_irradiance_q32[k]
  // for every node k (inner nodes 0). kOutOfRange, saying how many it needed,
  // when the refinement needs more new links than the pool holds; the output
  // is then untouched.
  // `workers` (may be null: all on the caller) share the sending; the
  // result is the same bits for any thread count.
  Status FirstShot(uint32_t root, const SurfaceEmitterShape& shape, const int64_t* coverage_q32,
                   int64_t* leaf_irradiance_q32, WorkerPool* workers = nullptr);
  // Fractional emissivity's first shot from the same coverage: every node
  // the emitter covers sends its covered fraction through its stored links,
  // nothing is refined (no new links, no pool). What a new FE light's first
  // sweep would gather from the emitter alone, so the sweeps can start one
  // bounce ahead as AR's do.
  Status FractionalFirstShot(uint32_t root, const int64_t* coverage_q32, int64_t* leaf_irradiance_q32,
                             WorkerPool* workers = nullptr);
  // New links the last successful FirstShot made.
  int last_links() const { return last_links_; }
  int pool_links() const { return static_cast<int>(parts_[0].pool.size()); }

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
    // First moment of the covered fraction about the node's centre (Q32 x m,
    // u and v): null where it is zero or not used (leaves, whole nodes, FE).
    const int64_t* moment_q32;
  };
  // One of the two shares of a placement's sources. FirstShot always cuts
  // the walk's sources in two, alternately, whatever the thread count, and
  // adds the shares in order, so the bits never depend on it. A share's
  // pool holds as many links as the whole placement may make; the
  // placement is refused when the two together need more.
  struct Part {
    std::vector<NewLink> pool;
    size_t needed = 0;
    std::vector<int64_t> e0, eu, ev;  // per node: plain sends' light and gradients
  };
  static constexpr int kParts = 2;
  static constexpr int64_t kOne = int64_t{1} << 32;  // a covered fraction or ratio of 1, Q32
  // A job: a source node of the walk, with this bit set where the emitter
  // cuts it (else the node is wholly inside, with all its subtree).
  static constexpr uint32_t kPartialJob = 0x80000000u;
  static void Bound(const int64_t (*poly)[3], int count, int64_t centre[3], int64_t* radius);
  void AddJobs(uint32_t node);
  // clip: null for FractionalFirstShot (every link sends its share).
  void RunPart(int part, const EmitterClip3* clip);
  Status Shoot(uint32_t root, const SurfaceEmitterShape* shape, const int64_t* coverage_q32,
               int64_t* leaf_irradiance_q32, WorkerPool* workers);
  // The sending reads the tables and writes only `part`: two parts run at once.
  // moment_q32: the source's Source::moment_q32 (may be null).
  void Send(Part& part, uint32_t link_side, uint64_t ratio_q32, const int64_t* moment_q32 = nullptr) const;
  void SendLink(Part& part, const Source& source, uint32_t link_side) const;
  int64_t MomentTerm(uint32_t link, bool from_p, const int64_t* moment_q32) const;
  // Sum of F from the receiver's quadrature points to the polygon; with
  // `gradient`, also the least-squares slope of F over them (Q32 per metre).
  // centre, radius: Bound() of the polygon the points are compared with.
  uint64_t SumFactorsQ32(uint32_t receiver, const int64_t (*poly)[3], int count, const int64_t centre[3],
                         int64_t radius, int64_t gradient_q32[2] = nullptr) const;
  bool Far(uint32_t receiver, const int64_t centre[3], int64_t radius) const;
  void RefineReceiver(Part& part, uint32_t node, const Source& source, uint64_t visibility_q32,
                      uint64_t reverse_q32) const;
  void Add(Part& part, uint32_t receiver, int64_t e0, int64_t eu, int64_t ev) const;
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
  std::vector<int64_t> coverage_mean_q32_;
  std::vector<int64_t> coverage_moment_q32_;  // 2 per node: Source::moment_q32
  Part parts_[kParts];
  std::vector<uint32_t> jobs_;  // capacity: every node once
  uint32_t job_count_ = 0;
  uint64_t refine_threshold_q32_ = 0;  // 2^(32 - refine_bits)
  int last_links_ = 0;
};

}  // namespace relight
