#include "hierarchy_solve.h"

#include <algorithm>
#include <cmath>

#include "gather_kernel.h"
#include "parallel_for.h"
#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using radiosity_vec::Dot;

// Columns per block. A luminaire's terms split into several blocks so both
// cores get work; at most 48 makes a degree-8 luminaire's 81 terms two
// blocks per colour channel, six in all, which two cores share evenly (at
// 32 they made nine, the last one running alone). A block's arrays outgrow
// the cache at venue size either way (docs/venue.md). The split depends on
// the terms only, never on the threads, so bakes do not either.
constexpr Eigen::Index kMaxBlockColumns = 48;

using Row = Eigen::Map<Eigen::ArrayXd>;
using ConstRow = Eigen::Map<const Eigen::ArrayXd>;

}  // namespace

HierarchicalSolver::HierarchicalSolver(Hierarchy hierarchy, std::vector<HierarchyLink> links,
                                       const std::vector<Rgb>& rho,
                                       const HierarchicalSolveOptions& options,
                                       ClusterSystem clusters)
    : hierarchy_(std::move(hierarchy)),
      links_(std::move(links)),
      clusters_(std::move(clusters)),
      options_(options) {
  const auto n_patches = static_cast<Eigen::Index>(rho.size());
  for (int c = 0; c < 3; ++c) {
    rho_[c].resize(n_patches);
    for (Eigen::Index i = 0; i < n_patches; ++i) rho_[c](i) = rho[static_cast<size_t>(i)][c];
  }
  for (int c = 0; c < 3; ++c) {
    same_as_[c] = c;
    for (int d = 0; d < c; ++d) {
      if (same_as_[d] == d && rho_[d] == rho_[c]) {
        same_as_[c] = d;
        break;
      }
    }
  }
  const size_t n = hierarchy_.nodes.size();
  gather_offsets_.assign(n + 1, 0);
  for (const HierarchyLink& l : links_) {
    if (l.f_pq > 0) ++gather_offsets_[l.p + 1];
    if (l.f_qp > 0) ++gather_offsets_[l.q + 1];
  }
  for (size_t k = 0; k < n; ++k) gather_offsets_[k + 1] += gather_offsets_[k];
  gather_source_.resize(gather_offsets_[n]);
  gather_factor_.resize(kGatherCoefficients * gather_offsets_[n]);
  std::vector<uint32_t> fill(gather_offsets_.begin(), gather_offsets_.end() - 1);
  // The source's side of a link: how much of the light `to` gathers comes
  // from each part of `from` is, by reciprocity, how much of to's light
  // reaches that part: the reverse factor's linear field f_rev + g_rev . x
  // over `from`. Weighting from's exitance by it, rather than taking its
  // plain mean, gives the mean irradiance on `to`
  //   f (B_mean + (g_rev / f_rev) . m),  m = mean of B (x - c) over `from`,
  // m being from's first moment of exitance (zero for a leaf).
  const auto add = [&](uint32_t to, uint32_t from, double f, const std::array<double, 2>& g,
                       double f_rev, const std::array<double, 2>& g_rev) {
    const uint32_t e = fill[to]++;
    gather_source_[e] = from;
    float* c = &gather_factor_[kGatherCoefficients * e];
    c[0] = static_cast<float>(f);
    c[1] = static_cast<float>(g[0]);
    c[2] = static_cast<float>(g[1]);
    const bool moment = options_.source_moments && !hierarchy_.nodes[from].leaf() && f_rev > 0;
    c[3] = moment ? static_cast<float>(f * g_rev[0] / f_rev) : 0.0F;
    c[4] = moment ? static_cast<float>(f * g_rev[1] / f_rev) : 0.0F;
  };
  for (const HierarchyLink& l : links_) {
    if (l.f_pq > 0) add(l.p, l.q, l.f_pq, l.g_pq, l.f_qp, l.g_qp);
    if (l.f_qp > 0) add(l.q, l.p, l.f_qp, l.g_qp, l.f_pq, l.g_pq);
  }
  child_weight_.assign(n, 0);
  centre_uv_.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const HierarchyNode& node = hierarchy_.nodes[k];
    if (node.parent != kNoNode) {
      child_weight_[k] = node.area_m2 / hierarchy_.nodes[node.parent].area_m2;
    }
    centre_uv_[k] = hierarchy_.PlaneCoords(node.surface, node.centre);
  }
  BuildCarry();
}

void HierarchicalSolver::BuildCarry() {
  const std::vector<HierarchyNode>& nodes = hierarchy_.nodes;
  struct Directed {
    uint32_t to;
    CarryEntry entry;
  };
  std::vector<Directed> directed;
  directed.reserve(2 * clusters_.links.size());
  // Light from `from` towards `dir` (unit, leaving it), times `scale`, onto
  // `to`, arriving from -dir (cluster_links.h).
  const auto add = [&](uint32_t from, uint32_t to, const Vec3& dir, double scale) {
    if (scale == 0) return;
    CarryEntry e;
    e.from = from;
    if (IsCluster(from)) {
      for (int i = 0; i < 3; ++i) {
        if (dir[i] == 0) continue;
        e.from_bin[e.n_from] = static_cast<uint8_t>(ClusterBin(i, dir[i]));
        e.from_weight[e.n_from++] = scale * std::abs(dir[i]);
      }
    } else {
      e.from_weight[e.n_from++] = scale;
    }
    if (IsCluster(to)) {
      for (int i = 0; i < 3; ++i) {
        if (dir[i] == 0) continue;
        e.to_bin[e.n_to] = static_cast<uint8_t>(ClusterBin(i, -dir[i]));
        e.to_weight[e.n_to++] = std::abs(dir[i]);
      }
    } else {
      const double cosine = -Dot(nodes[to].normal, dir);
      if (!(cosine > 0)) return;
      e.to_weight[e.n_to++] = cosine;
    }
    directed.push_back({to, e});
  };
  for (const ClusterLink& l : clusters_.links) {
    const Vec3 back{-l.direction[0], -l.direction[1], -l.direction[2]};
    add(l.a, l.b, l.direction, l.a_to_b);
    add(l.b, l.a, back, l.b_to_a);
  }
  // Stable: within a receiver, the links' order (sorted by (a, b)).
  std::stable_sort(directed.begin(), directed.end(),
                   [](const Directed& x, const Directed& y) { return x.to < y.to; });
  carry_entries_.reserve(directed.size());
  for (size_t k = 0; k < directed.size(); ++k) {
    if (k == 0 || directed[k].to != directed[k - 1].to) {
      const auto at = static_cast<uint32_t>(k);
      carry_targets_.push_back({directed[k].to, at, at});
    }
    carry_entries_.push_back(directed[k].entry);
    ++carry_targets_.back().end;
  }
}

std::vector<HierarchicalSolver::Task> HierarchicalSolver::Tasks(const std::vector<int>& channels,
                                                                Eigen::Index columns) const {
  std::vector<Task> tasks;
  if (columns == 0) return tasks;
  const Eigen::Index blocks = (columns + kMaxBlockColumns - 1) / kMaxBlockColumns;
  const Eigen::Index width = (columns + blocks - 1) / blocks;
  for (int c : channels) {
    for (Eigen::Index col = 0; col < columns; col += width) {
      tasks.push_back({c, col, std::min(width, columns - col)});
    }
  }
  return tasks;
}

void HierarchicalSolver::RunTasks(const std::vector<Task>& tasks, const Eigen::MatrixXd& rhs,
                                  bool rhs_is_illuminance,
                                  std::array<Eigen::MatrixXd, 3>* out) const {
  // Each task writes its own columns of one channel's result: no locks.
  ParallelFor(tasks.size(), options_.threads, [&](size_t k, int) {
    SolveBlock(tasks[k], rhs, rhs_is_illuminance, &(*out)[tasks[k].channel]);
  });
}

Eigen::MatrixXd HierarchicalSolver::Solve(int channel, const Eigen::MatrixXd& emitted) const {
  std::array<Eigen::MatrixXd, 3> out;
  out[channel].resize(emitted.rows(), emitted.cols());
  RunTasks(Tasks({channel}, emitted.cols()), emitted, false, &out);
  return std::move(out[channel]);
}

Eigen::MatrixXd HierarchicalSolver::SolveExitance(int channel,
                                                  const Eigen::MatrixXd& illuminance_lux) const {
  std::array<Eigen::MatrixXd, 3> out;
  out[channel].resize(illuminance_lux.rows(), illuminance_lux.cols());
  RunTasks(Tasks({channel}, illuminance_lux.cols()), illuminance_lux, true, &out);
  return std::move(out[channel]);
}

std::array<Eigen::MatrixXd, 3> HierarchicalSolver::SolveExitanceRgb(
    const Eigen::MatrixXd& illuminance_lux) const {
  std::vector<int> distinct;
  for (int c = 0; c < 3; ++c)
    if (same_as_[c] == c) distinct.push_back(c);
  std::array<Eigen::MatrixXd, 3> out;
  for (int c : distinct) out[c].resize(illuminance_lux.rows(), illuminance_lux.cols());
  RunTasks(Tasks(distinct, illuminance_lux.cols()), illuminance_lux, true, &out);
  for (int c = 0; c < 3; ++c)
    if (same_as_[c] != c) out[c] = out[same_as_[c]];
  return out;
}

void HierarchicalSolver::SolveBlock(const Task& task, const Eigen::MatrixXd& rhs,
                                    bool rhs_is_illuminance, Eigen::MatrixXd* out) const {
  const std::vector<HierarchyNode>& nodes = hierarchy_.nodes;
  const size_t n = nodes.size();
  const Eigen::Index w = task.width;
  // A row holds the block's w columns, padded with zeros to whole vectors
  // for the gather kernel; the padding stays zero throughout.
  const size_t ws = (static_cast<size_t>(w) + kGatherLanes - 1) / kGatherLanes * kGatherLanes;
  const Eigen::VectorXd& rho = rho_[task.channel];
  // Node-major blocks: row k of a block is node k's w columns. b: exitance
  // (a node's is its leaves' area mean); mu, mv: its first moment about the
  // node's centre (surface frame, m; 0 at a leaf). g0, gu, gv: gathered
  // irradiance a + b u + c v over the node.
  std::vector<double> s(n * ws, 0.0), b(n * ws, 0.0), mu(n * ws, 0.0), mv(n * ws, 0.0);
  std::vector<double> g0(n * ws, 0.0), gu(n * ws, 0.0), gv(n * ws, 0.0);
  // With clusters: ge, irradiance per node over the cluster links (constant
  // over the node); out_bins, in_bins: each cluster's six bins, leaving and
  // arriving (cluster_tree.h).
  const auto wp = static_cast<Eigen::Index>(ws);
  const bool clustered = !clusters_.tree.empty();
  const size_t bin_rows = kClusterBins * clusters_.tree.clusters.size();
  std::vector<double> ge(clustered ? n * ws : 0, 0.0);
  std::vector<double> out_bins(bin_rows * ws, 0.0), in_bins(bin_rows * ws, 0.0);
  const auto row = [ws](std::vector<double>& v, size_t k) { return Row(v.data() + k * ws, ws); };
  const auto crow = [ws](const std::vector<double>& v, size_t k) {
    return ConstRow(v.data() + k * ws, ws);
  };
  for (size_t k = 0; k < n; ++k) {
    if (!nodes[k].leaf()) continue;
    const auto i = static_cast<Eigen::Index>(nodes[k].patch);
    const double scale = rhs_is_illuminance ? rho(i) : 1.0;
    for (Eigen::Index j = 0; j < w; ++j) s[k * ws + j] = scale * rhs(i, task.column + j);
  }
  b = s;
  // Pull: exitance and its moment up the tree as area-weighted sums.
  const auto pull = [&](size_t begin, size_t end) {
    // Parents come before children: in reverse, children are done first.
    for (size_t k = end; k-- > begin;) {
      const HierarchyNode& node = nodes[k];
      if (node.leaf()) continue;
      Row bk = row(b, k), uk = row(mu, k), vk = row(mv, k);
      bk.setZero();
      uk.setZero();
      vk.setZero();
      for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c) {
        const double wc = child_weight_[c];
        const ConstRow bc = crow(b, c);
        bk += wc * bc;
        uk += wc * crow(mu, c) + (wc * (centre_uv_[c][0] - centre_uv_[k][0])) * bc;
        vk += wc * crow(mv, c) + (wc * (centre_uv_[c][1] - centre_uv_[k][1])) * bc;
      }
    }
  };
  const size_t surfaces = hierarchy_.surface_count();
  for (size_t sf = 0; sf < surfaces; ++sf)
    pull(hierarchy_.surface_begin[sf], hierarchy_.surface_begin[sf + 1]);

  // The light over the cluster links from the current exitance, into ge.
  const auto cluster_pass = [&]() {
    const ClusterTree& tree = clusters_.tree;
    const auto bin = [&](std::vector<double>& v, size_t cluster, int k) {
      return Row(v.data() + (kClusterBins * cluster + static_cast<size_t>(k)) * ws, ws);
    };
    // Leaving: members' exitance x area into the bins, children before parents.
    for (size_t c = tree.clusters.size(); c-- > 0;) {
      for (int k = 0; k < kClusterBins; ++k) bin(out_bins, c, k).setZero();
      for (uint32_t child : tree.clusters[c].children) {
        if (IsCluster(child)) {
          for (int k = 0; k < kClusterBins; ++k)
            bin(out_bins, c, k) += bin(out_bins, ClusterIndex(child), k);
          continue;
        }
        const HierarchyNode& root = nodes[child];
        const auto& weights = tree.surface_bins[root.surface];
        for (int k = 0; k < kClusterBins; ++k)
          if (weights[static_cast<size_t>(k)] > 0)
            bin(out_bins, c, k) +=
                (weights[static_cast<size_t>(k)] * root.area_m2) * crow(b, child);
      }
    }
    std::fill(in_bins.begin(), in_bins.end(), 0.0);
    std::fill(ge.begin(), ge.end(), 0.0);
    // Each receiving element gathers its links (BuildCarry) into its rows.
    for (const CarryTarget& t : carry_targets_) {
      const bool to_cluster = IsCluster(t.to);
      double* to_base =
          to_cluster ? bin(in_bins, ClusterIndex(t.to), 0).data() : row(ge, t.to).data();
      for (uint32_t k = t.begin; k < t.end; ++k) {
        const CarryEntry& e = carry_entries_[k];
        const double* from_rows[3];
        double* to_rows[3];
        if (IsCluster(e.from)) {
          const size_t c = ClusterIndex(e.from);
          for (int i = 0; i < e.n_from; ++i) from_rows[i] = bin(out_bins, c, e.from_bin[i]).data();
        } else {
          from_rows[0] = crow(b, e.from).data();
        }
        for (int i = 0; i < e.n_to; ++i) to_rows[i] = to_base + e.to_bin[i] * ws;
        CarryLight(from_rows, e.from_weight.data(), e.n_from, to_rows, e.to_weight.data(), e.n_to,
                   ws);
      }
    }
    // Arriving: down to the members, parents before children.
    for (size_t c = 0; c < tree.clusters.size(); ++c) {
      for (uint32_t child : tree.clusters[c].children) {
        if (IsCluster(child)) {
          for (int k = 0; k < kClusterBins; ++k)
            bin(in_bins, ClusterIndex(child), k) += bin(in_bins, c, k);
          continue;
        }
        const auto& weights = tree.surface_bins[nodes[child].surface];
        for (int k = 0; k < kClusterBins; ++k)
          if (weights[static_cast<size_t>(k)] > 0)
            row(ge, child) += weights[static_cast<size_t>(k)] * bin(in_bins, c, k);
      }
    }
  };

  // Every node of surface sf gathers from the current exitance of the others
  // (a planar surface never sees itself), and the light is pushed down: a
  // leaf's row of g0 is then its mean irradiance.
  const GatherSources sources{b.data(), mu.data(), mv.data(), ws};
  const auto gather = [&](size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) {
      Row a = row(g0, k);
      const uint32_t e0 = gather_offsets_[k], e1 = gather_offsets_[k + 1];
      const bool inner = !nodes[k].leaf();
      Row du = row(gu, k), dv = row(gv, k);
      GatherNode(sources, gather_source_.data() + e0,
                 gather_factor_.data() + kGatherCoefficients * e0, e1 - e0, inner, a.data(),
                 du.data(), dv.data());
      // About the surface's origin rather than the node's centre, so
      // that a child can add its parent's coefficients as they are.
      if (inner) a -= centre_uv_[k][0] * du + centre_uv_[k][1] * dv;
      if (clustered) a += crow(ge, k);
    }
    // Push: irradiance gathered at a node reaches all of its area; a leaf
    // takes the linear irradiance at its centre (its mean over the leaf).
    for (size_t k = begin + 1; k < end; ++k) {
      const size_t parent = nodes[k].parent;
      row(g0, k) += crow(g0, parent);
      if (nodes[k].leaf()) {
        row(g0, k) += centre_uv_[k][0] * crow(gu, parent) + centre_uv_[k][1] * crow(gv, parent);
      } else {
        row(gu, k) += crow(gu, parent);
        row(gv, k) += crow(gv, parent);
      }
    }
  };

  // Columns that are all but zero next to the block's largest do not hold
  // the iteration up: relative figures are taken over the others.
  const auto worst_relative = [&](const Eigen::ArrayXd& value, const Eigen::ArrayXd& peak) {
    const double block_peak = peak.maxCoeff();
    double worst = 0;
    for (Eigen::Index j = 0; j < w; ++j)
      if (peak(j) > 1e-12 * block_peak) worst = std::max(worst, value(j) / peak(j));
    return worst;
  };
  // The residual r = S + rho K B - B of the current B, largest over the
  // leaves, relative to each column's peak exitance (one extra gather).
  const auto residual = [&]() {
    if (clustered) cluster_pass();
    Eigen::ArrayXd r = Eigen::ArrayXd::Zero(wp), peak = Eigen::ArrayXd::Zero(wp);
    for (size_t sf = 0; sf < surfaces; ++sf) {
      const size_t begin = hierarchy_.surface_begin[sf], end = hierarchy_.surface_begin[sf + 1];
      gather(begin, end);
      for (size_t k = begin; k < end; ++k) {
        if (!nodes[k].leaf()) continue;
        const double rk = rho(static_cast<Eigen::Index>(nodes[k].patch));
        r = r.max((crow(s, k) + rk * crow(g0, k) - crow(b, k)).abs());
        peak = peak.max(crow(b, k).abs());
      }
    }
    return worst_relative(r, peak);
  };

  // The error of B is at most |r| / (1 - rho_max) (the links' rows sum to
  // about 1, so rho K shrinks any vector by rho_max): stopping at
  // |r| <= tolerance (1 - rho_max) peak bounds the error by tolerance x peak.
  const double rho_max = std::min(rho.size() > 0 ? rho.maxCoeff() : 0.0, 0.999);
  const double residual_bar = options_.tolerance * (1 - rho_max);
  Eigen::ArrayXd change(wp), peak(wp), updated(wp);
  double previous = 0, stopped_at = 0;
  int sweep = 0;
  while (sweep < options_.max_sweeps) {
    ++sweep;
    change.setZero();
    peak.setZero();
    if (clustered) cluster_pass();
    // Gauss-Seidel over surfaces: each gathers the latest exitance of the others.
    for (size_t sf = 0; sf < surfaces; ++sf) {
      const size_t begin = hierarchy_.surface_begin[sf], end = hierarchy_.surface_begin[sf + 1];
      gather(begin, end);
      for (size_t k = begin; k < end; ++k) {
        if (!nodes[k].leaf()) continue;
        const double r = rho(static_cast<Eigen::Index>(nodes[k].patch));
        updated = crow(s, k) + r * crow(g0, k);
        Row bk = row(b, k);
        change = change.max((updated - bk).abs());
        peak = peak.max(updated.abs());
        bk = updated;
      }
      pull(begin, end);
    }
    // The sweeps' change only says when to look: the last change times
    // r / (1 - r), r the observed contraction, estimates what is left. The
    // residual, measured then, decides.
    const double worst = worst_relative(change, peak);
    const double rate = sweep >= 2 && previous > 0 ? std::clamp(worst / previous, 0.0, 0.99) : 0.99;
    previous = worst;
    if (worst != 0 && worst * rate / (1 - rate) >= options_.tolerance) continue;
    stopped_at = residual();
    if (stopped_at <= residual_bar) break;
  }
  if (sweep >= options_.max_sweeps) stopped_at = residual();
  int seen = max_sweeps_used_.load();
  while (sweep > seen && !max_sweeps_used_.compare_exchange_weak(seen, sweep)) {
  }
  double seen_residual = max_residual_.load();
  while (stopped_at > seen_residual &&
         !max_residual_.compare_exchange_weak(seen_residual, stopped_at)) {
  }
  for (size_t k = 0; k < n; ++k) {
    if (!nodes[k].leaf()) continue;
    const auto i = static_cast<Eigen::Index>(nodes[k].patch);
    for (Eigen::Index j = 0; j < w; ++j) (*out)(i, task.column + j) = b[k * ws + j];
  }
}

}  // namespace relight::baker
