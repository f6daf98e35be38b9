// The hierarchical solve's inner loops (hierarchy_solve.cc): one node gathers
// the light of its links for every column of a block at once, and a cluster
// link carries light between direction bins and nodes. Kept apart so
// it can be compiled for wider vector units than the baseline x86-64 (SSE2)
// and picked at run time: element by element the operations and their order
// are the same on every path (no fused multiply-add), so bakes stay the same
// bit for bit on every machine, which distributed bakes rely on.
#pragma once

#include <cstddef>
#include <cstdint>

namespace relight::baker {

// Per gather entry: the mean factor, its gradient over the receiver (u, v)
// and the weights of the source's exitance moment (u, v).
constexpr size_t kGatherCoefficients = 5;

// Columns per row are padded to a multiple of this (zeros in the padding).
constexpr size_t kGatherLanes = 4;

// Node-major blocks of `width` columns a row (width a multiple of
// kGatherLanes): b exitance, mu and mv its first moment.
struct GatherSources {
  const double* b;
  const double* mu;
  const double* mv;
  size_t width;
};

// For entries e in [0, count): source row q = source[e], factors
// f = factor + 5 e (mean, d/du, d/dv over the receiver, weights of the
// source's moment u, v; float: a venue's default refinement has tens of
// millions of entries, and a float is within 6e-8 of the factor, far inside
// the solve's 1e-5 tolerance; the sums are in double):
//   a += f0 b_q, then a += f3 mu_q + f4 mv_q when f3 or f4 is not zero,
//   and with `inner`: du += f1 b_q, dv += f2 b_q.
// a (and du, dv with `inner`) are set to zero first.
void GatherNode(const GatherSources& src, const uint32_t* source, const float* factor,
                uint32_t count, bool inner, double* a, double* du, double* dv);

// Light carried over one cluster link, per column j < width:
//   light = sum over i < n_from of from_weight[i] from[i][j] (in that order),
//   then to[k][j] += to_weight[k] light for every k < n_to.
// At most 3 rows each side (a cluster's direction bins, or one node's row).
void CarryLight(const double* const* from, const double* from_weight, int n_from, double* const* to,
                const double* to_weight, int n_to, size_t width);

}  // namespace relight::baker
