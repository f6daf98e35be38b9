// The radiosity system on the hierarchy (Hanrahan, Salzman & Aupperle 1991):
//   M = S + rho (K M),  K = push . links . pull
// solved by Gauss-Seidel sweeps over the surfaces' quadtrees: per surface,
// every node gathers irradiance over its links (F times the source node's
// exitance, varying linearly over the node by the links' gradients; the
// source's exitance weighted linearly over it by the reverse gradient), the
// gathered irradiance is pushed down to the leaves (evaluated at each leaf's
// centre, which is its mean), leaves take M = S + rho E_gathered, and
// exitance and its first moment are pulled up as area-weighted sums. Every right-hand side
// (all SH terms of a luminaire, Dobashi Eq. 17) goes through one sweep as a
// dense block of columns, since the links (F) are shared by all of them.
// Columns are split into blocks that run on separate threads.
// Thread safety: Solve*() are const and may run concurrently.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <atomic>
#include <vector>

#include "cluster_links.h"
#include "cluster_tree.h"
#include "hierarchy.h"
#include "hierarchy_links.h"
#include "relight/baker/scene.h"

namespace relight::baker {

struct HierarchicalSolveOptions {
  // The sweeps stop when the residual |S + rho K B - B| of every column, the
  // largest over the leaves relative to that column's largest leaf
  // exitance, is at most tolerance x (1 - rho_max): the error of B is then
  // at most tolerance x peak. (The residual costs a gather; it is measured
  // once the sweeps' estimated remaining change is below the tolerance.)
  double tolerance = 1e-5;
  // Weight a source node's exitance by where its light reaches the receiver
  // (the link's reverse gradient times the node's first moment of exitance)
  // instead of taking its mean: without it a coarse link misses how the
  // exitance varies over its source, which darkens rooms by ~0.5 %
  // (docs/hierarchy.md, "Bias and its fix"). Off: the stored links' plain
  // operator, as the runtime's solve uses it.
  bool source_moments = true;
  int max_sweeps = 500;
  int threads = 0;  // 0 = every core
};

// Clusters above the quadtrees and their links (cluster_links.h); empty
// when the refinement started from every pair of surfaces.
struct ClusterSystem {
  ClusterTree tree;
  std::vector<ClusterLink> links;
};

class HierarchicalSolver {
 public:
  // rho: per mesh patch RGB reflectance. With clusters, each sweep first
  // carries the light over the cluster links (from the previous sweep's
  // exitance: Jacobi for that small part), as constant irradiance per node.
  HierarchicalSolver(Hierarchy hierarchy, std::vector<HierarchyLink> links,
                     const std::vector<Rgb>& rho, const HierarchicalSolveOptions& options,
                     ClusterSystem clusters = {});

  // Solves M = S + rho_c K M for the emitted exitance S (patches x k); M is
  // the total exitance (lm/m^2) per patch.
  Eigen::MatrixXd Solve(int channel, const Eigen::MatrixXd& emitted) const;
  // Exitance M (lm/m^2) from direct illuminance E (lux): S = rho_c E.
  Eigen::MatrixXd SolveExitance(int channel, const Eigen::MatrixXd& illuminance_lux) const;
  // All three channels at once (channels with equal reflectances solved once).
  std::array<Eigen::MatrixXd, 3> SolveExitanceRgb(const Eigen::MatrixXd& illuminance_lux) const;

  const Eigen::VectorXd& reflectance(int channel) const { return rho_[channel]; }
  const Hierarchy& hierarchy() const { return hierarchy_; }
  // The links as refined. Empty after ReleaseLinks(): the solve itself
  // gathers from lists built at construction.
  const std::vector<HierarchyLink>& links() const { return links_; }
  // Frees links() (56 bytes a link, 1.5 GB on the 100k venue's default
  // refinement) once their bake encoding is made; solving is unaffected.
  void ReleaseLinks() { std::vector<HierarchyLink>().swap(links_); }
  const ClusterSystem& clusters() const { return clusters_; }
  // Most sweeps any column block needed so far.
  int max_sweeps_used() const { return max_sweeps_used_.load(); }
  // Largest relative residual any column block stopped at so far.
  double max_residual() const { return max_residual_.load(); }

 private:
  struct Task {
    int channel;
    Eigen::Index column, width;
  };
  void RunTasks(const std::vector<Task>& tasks, const Eigen::MatrixXd& rhs, bool rhs_is_illuminance,
                std::array<Eigen::MatrixXd, 3>* out) const;
  void SolveBlock(const Task& task, const Eigen::MatrixXd& rhs, bool rhs_is_illuminance,
                  Eigen::MatrixXd* out) const;
  std::vector<Task> Tasks(const std::vector<int>& channels, Eigen::Index columns) const;

  Hierarchy hierarchy_;
  std::vector<HierarchyLink> links_;
  ClusterSystem clusters_;
  HierarchicalSolveOptions options_;
  std::array<Eigen::VectorXd, 3> rho_;
  std::array<int, 3> same_as_{};  // channel whose reflectances this one repeats (itself if none)
  // Gather lists: node n gathers from gather_source[k] with factor
  // gather_factor[k] (5 per entry: mean, d/du, d/dv over n, weights of the
  // source's exitance moment u, v; float: gather_kernel.h says why),
  // k in [gather_offsets[n], gather_offsets[n + 1]).
  std::vector<uint32_t> gather_offsets_, gather_source_;
  std::vector<float> gather_factor_;
  // The cluster links as their receiving elements gather them: entries
  // grouped by `to`, so each element's rows are written while they are in
  // the cache, not once per link at scattered places. A link gives two
  // entries (one per direction); the light leaving `from` towards the
  // receiver is its rows (a cluster's direction bins, or a node's exitance)
  // weighted by from_weight, and it arrives at `to`'s rows (bins, or the
  // node's irradiance) weighted by to_weight.
  struct CarryEntry {
    uint32_t from = 0;
    uint8_t n_from = 0, n_to = 0;
    std::array<uint8_t, 3> from_bin{}, to_bin{};
    std::array<double, 3> from_weight{}, to_weight{};
  };
  struct CarryTarget {
    uint32_t to = 0, begin = 0, end = 0;  // entries [begin, end)
  };
  void BuildCarry();
  std::vector<CarryEntry> carry_entries_;
  std::vector<CarryTarget> carry_targets_;
  std::vector<double> child_weight_;  // area of a node over its parent's
  std::vector<std::array<double, 2>> centre_uv_;  // per node, in its surface's frame
  mutable std::atomic<int> max_sweeps_used_{0};
  mutable std::atomic<double> max_residual_{0.0};
};

}  // namespace relight::baker
