// The hierarchy and links the baker stores (sections HIER and LINK): only the
// hierarchical solver stores them, --no-hierarchy (store_hierarchy = false)
// leaves them out, they survive the file unchanged, and they are complete: a
// float64 solve that reads nothing but the bake file reproduces the baker's
// own hierarchical solve of the same emission.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "bake_hierarchy.h"
#include "grid_links.h"
#include "bake_test_bake.h"
#include "baker_core.h"
#include "radiosity_vec.h"
#include "relight/bake/bake.h"
#include "relight/baker/baker.h"
#include "test_scenes.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

// The Cornell box (1300 patches of quads, blocks that hide and straddle,
// coloured walls) plus a triangle leaning in a corner (a triangle grid's
// hexagonal nodes and one-triangle leaves).
Scene CornellWithLeanTo() {
  Scene scene = LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/cornell_box.toml");
  scene.surfaces.push_back(test_scenes::Triangle("lean-to", {0.05, -0.45, 0.0},
                                                 {0.15, -0.555, 0.2}, {0.25, -0.45, 0.0},
                                                 {0.6, 0.5, 0.4}));
  return scene;
}

BakeOptions Hierarchical() {
  BakeOptions options;
  options.solver = SolverKind::kHierarchical;
  options.solve_tolerance = 1e-9;  // the comparison below measures storage, not sweeps
  return options;
}

class TempDir {
 public:
  TempDir() {
    char tmpl[] = "/tmp/bake_hierarchy_test.XXXXXX";
    path_ = ::mkdtemp(tmpl) ? tmpl : "";
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string File(const char* name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

relight::Bake WriteAndRead(const relight::Bake& bake, const std::string& path) {
  std::vector<BakeSectionSize> sizes;
  Status st = WriteBake(bake, path, &sizes);
  EXPECT_TRUE(st.ok()) << st.ToString();
  relight::Bake read;
  st = ReadBake(path, &read);
  EXPECT_TRUE(st.ok()) << st.ToString();
  return read;
}

// --- A radiosity solve from the stored form alone --------------------------------------
// Everything comes from the bake: node trees, areas (Q32.32), corner vertices
// (Q16.16 positions) for the node centres and surface frames, links (UQ0.32
// factors, Q8.23 gradients), leaves' reflectance (MESH albedo of a corner).
// Gauss-Seidel over surfaces as docs/hierarchy.md describes.
class StoredSolve {
 public:
  explicit StoredSolve(const relight::Bake& bake) : h_(*bake.hierarchy), mesh_(bake.mesh) {
    const size_t n = h_.node_count();
    centre_uv_.resize(n);
    child_weight_.assign(n, 0);
    for (size_t k = 0; k < n; ++k) {
      if (h_.node_parent[k] == kBakeNoIndex) SetFrame(k);
      const Vec3 d = Centroid(k) - origin_;
      centre_uv_[k] = {Dot(d, u_), Dot(d, v_)};
      if (h_.node_parent[k] != kBakeNoIndex) {
        child_weight_[k] = static_cast<double>(h_.node_area[k]) /
                           static_cast<double>(h_.node_area[h_.node_parent[k]]);
      }
      if (k == 0 || h_.node_surface[k] != h_.node_surface[k - 1]) run_begin_.push_back(k);
    }
    run_begin_.push_back(n);
    gathers_.resize(n);
    for (size_t i = 0; i < h_.link_count(); ++i) {
      const uint32_t p = h_.link_p[i], q = h_.link_q[i];
      // The source's exitance weighted by the reverse factor's gradient
      // over it (its first moment), as the baker's solver does.
      if (h_.link_f_pq[i] != 0)
        gathers_[p].emplace_back(q, h_.link_f_pq[i], &h_.link_g_pq[2 * i], h_.link_f_qp[i],
                                 &h_.link_g_qp[2 * i], !h_.leaf(q));
      if (h_.link_f_qp[i] != 0)
        gathers_[q].emplace_back(p, h_.link_f_qp[i], &h_.link_g_qp[2 * i], h_.link_f_pq[i],
                                 &h_.link_g_pq[2 * i], !h_.leaf(p));
    }
  }

  // Exitance per node (lm/m^2) for emitted exitance per node (leaves only).
  std::vector<double> Solve(int channel, const std::vector<double>& emitted) const {
    const size_t n = h_.node_count();
    std::vector<double> b = emitted, g0(n), gu(n), gv(n), mu(n), mv(n);
    for (size_t r = 0; r + 1 < run_begin_.size(); ++r)
      Pull(run_begin_[r], run_begin_[r + 1], &b, &mu, &mv);
    for (int sweep = 0; sweep < 2000; ++sweep) {
      double change = 0, peak = 0;
      for (size_t r = 0; r + 1 < run_begin_.size(); ++r) {
        const size_t begin = run_begin_[r], end = run_begin_[r + 1];
        for (size_t k = begin; k < end; ++k) {
          g0[k] = gu[k] = gv[k] = 0;
          for (const Gather& g : gathers_[k]) {
            g0[k] += g.f * b[g.source] + g.mu * mu[g.source] + g.mv * mv[g.source];
            gu[k] += g.du * b[g.source];
            gv[k] += g.dv * b[g.source];
          }
          // About the surface's origin, so children add it as it is.
          g0[k] -= centre_uv_[k][0] * gu[k] + centre_uv_[k][1] * gv[k];
        }
        for (size_t k = begin + 1; k < end; ++k) {  // push
          const uint32_t parent = h_.node_parent[k];
          g0[k] += g0[parent];
          gu[k] += gu[parent];
          gv[k] += gv[parent];
        }
        for (size_t k = begin; k < end; ++k) {
          if (!h_.leaf(static_cast<uint32_t>(k))) continue;
          // A leaf's mean irradiance: the linear field at its centre.
          const double e = g0[k] + centre_uv_[k][0] * gu[k] + centre_uv_[k][1] * gv[k];
          const double updated = emitted[k] + Reflectance(k, channel) * e;
          change = std::max(change, std::abs(updated - b[k]));
          peak = std::max(peak, std::abs(updated));
          b[k] = updated;
        }
        Pull(begin, end, &b, &mu, &mv);
      }
      if (change <= 1e-13 * peak) break;
    }
    return b;
  }

  double Reflectance(size_t node, int channel) const {
    const uint32_t corner = h_.node_corners[node * kBakeMaxNodeCorners];
    return mesh_.albedo[3 * size_t{corner} + static_cast<size_t>(channel)] / 65535.0;
  }
  Vec3 Position(uint32_t vertex) const {
    const int32_t* p = &mesh_.positions[3 * size_t{vertex}];
    return {p[0] / 65536.0, p[1] / 65536.0, p[2] / 65536.0};
  }

 private:
  struct Gather {
    Gather(uint32_t from, uint32_t factor, const int32_t* gradient, uint32_t reverse,
           const int32_t* reverse_gradient, bool inner_source)
        : source(from),
          f(std::ldexp(factor, -32)),
          du(std::ldexp(gradient[0], -kBakeGradientFracBits)),
          dv(std::ldexp(gradient[1], -kBakeGradientFracBits)) {
      if (!inner_source || reverse == 0) return;
      const double f_rev = std::ldexp(reverse, -32);
      mu = f * std::ldexp(reverse_gradient[0], -kBakeGradientFracBits) / f_rev;
      mv = f * std::ldexp(reverse_gradient[1], -kBakeGradientFracBits) / f_rev;
    }
    uint32_t source;
    double f, du, dv, mu = 0, mv = 0;
  };

  Vec3 Corner(size_t node, int k) const {
    return Position(h_.node_corners[node * kBakeMaxNodeCorners + static_cast<size_t>(k)]);
  }
  // u along the root's first edge, v = n x u with n the surface's (vertex) normal.
  void SetFrame(size_t root) {
    origin_ = Corner(root, 0);
    u_ = Normalized(Corner(root, 1) - origin_);
    const int16_t* nq = &mesh_.normals[3 * size_t{h_.node_corners[root * kBakeMaxNodeCorners]}];
    v_ = Cross(Normalized({nq[0] / 16384.0, nq[1] / 16384.0, nq[2] / 16384.0}), u_);
  }
  Vec3 Centroid(size_t node) const {
    Vec3 sum{0, 0, 0};
    double area = 0;
    const Vec3 a = Corner(node, 0);
    for (int k = 1; k + 1 < h_.node_corner_count[node]; ++k) {
      const Vec3 b = Corner(node, k), c = Corner(node, k + 1);
      const double t = 0.5 * Length(Cross(b - a, c - a));
      sum += (t / 3.0) * (a + b + c);
      area += t;
    }
    return (1.0 / area) * sum;
  }
  // Exitance (area mean) and its first moment about the node's centre.
  void Pull(size_t begin, size_t end, std::vector<double>* b, std::vector<double>* mu,
            std::vector<double>* mv) const {
    for (size_t k = end; k-- > begin;) {
      if (h_.leaf(static_cast<uint32_t>(k))) continue;
      double sum = 0, su = 0, sv = 0;
      const uint32_t first = h_.node_first_child[k];
      for (uint32_t c = first; c < first + h_.node_child_count[k]; ++c) {
        const double w = child_weight_[c];
        sum += w * (*b)[c];
        su += w * ((*mu)[c] + (centre_uv_[c][0] - centre_uv_[k][0]) * (*b)[c]);
        sv += w * ((*mv)[c] + (centre_uv_[c][1] - centre_uv_[k][1]) * (*b)[c]);
      }
      (*b)[k] = sum;
      (*mu)[k] = su;
      (*mv)[k] = sv;
    }
  }

  const BakeHierarchy& h_;
  const BakeMesh& mesh_;
  std::vector<std::array<double, 2>> centre_uv_;
  std::vector<double> child_weight_;
  std::vector<size_t> run_begin_;  // first node of each surface's tree, then the node count
  std::vector<std::vector<Gather>> gathers_;
  Vec3 origin_{}, u_{}, v_{};
};

// Leaf node -> the baker's patch, through the leaf's first render triangle
// (the mesher emits corner_count - 2 triangles per patch, in patch order).
std::vector<uint32_t> PatchOfLeaf(const BakeHierarchy& h, const Mesh& mesh) {
  std::vector<uint32_t> patch_of_triangle;
  for (uint32_t i = 0; i < mesh.patch_count(); ++i)
    patch_of_triangle.insert(patch_of_triangle.end(),
                             static_cast<size_t>(mesh.patches[i].corner_count - 2), i);
  std::vector<uint32_t> out(h.node_count(), kBakeNoIndex);
  for (uint32_t k = 0; k < h.node_count(); ++k)
    if (h.leaf(k)) out[k] = patch_of_triangle.at(h.node_leaf_triangle[k]);
  return out;
}

// Area-weighted mean over the leaves around each vertex, from the bake alone.
std::vector<double> LeavesToVertices(const relight::Bake& bake, const std::vector<double>& node) {
  const BakeHierarchy& h = *bake.hierarchy;
  std::vector<double> sum(bake.mesh.vertex_count(), 0), area(bake.mesh.vertex_count(), 0);
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (!h.leaf(k)) continue;
    const double a = static_cast<double>(h.node_area[k]);
    for (int c = 0; c < h.node_corner_count[k]; ++c) {
      const uint32_t v = h.node_corners[size_t{k} * kBakeMaxNodeCorners + static_cast<size_t>(c)];
      sum[v] += a * node[k];
      area[v] += a;
    }
  }
  for (size_t v = 0; v < sum.size(); ++v) sum[v] = area[v] > 0 ? sum[v] / area[v] : 0;
  return sum;
}

double MaxOverPeak(const std::vector<double>& got, const Eigen::VectorXd& want) {
  double worst = 0;
  for (size_t i = 0; i < got.size(); ++i)
    worst = std::max(worst, std::abs(got[i] - want(static_cast<Eigen::Index>(i))));
  return worst / want.cwiseAbs().maxCoeff();
}

TEST(StoredHierarchy, OnlyTheHierarchicalSolverStoresItAndNoHierarchyLeavesItOut) {
  // Dense and --no-hierarchy bakes need a luminaire (a scene without one is
  // an error unless the bake stores its links for run-time emitters).
  const Scene lit = CornellWithLeanTo();
  BakeOptions dense;
  dense.solver = SolverKind::kDense;
  EXPECT_FALSE(Baker(lit, dense).Bake().hierarchy.has_value());
  BakeOptions without = Hierarchical();
  without.store_hierarchy = false;
  EXPECT_FALSE(Baker(lit, without).Bake().hierarchy.has_value());
  const Scene scene = test_scenes::ClosedBox(0.25, {0.5, 0.5, 0.5});
  Baker with(scene, Hierarchical());
  const relight::Bake bake = with.Bake();
  ASSERT_TRUE(bake.hierarchy.has_value());
  EXPECT_EQ(bake.hierarchy->node_count(), with.report().nodes);
  EXPECT_EQ(bake.hierarchy->link_count(), with.report().links);
}

// Write -> read gives back exactly what the baker made of its solver's
// hierarchy, and the stored nodes are the solver's, one for one.
TEST(StoredHierarchy, RoundTripKeepsTheSolversNodesAndLinks) {
  const Scene scene = CornellWithLeanTo();
  const auto core = BuildBakerCore(scene, Hierarchical(), nullptr);
  const HierarchicalSolver& solver = *core->hierarchical_solver;
  BakeHierarchy made = MakeBakeHierarchy(core->mesh, solver.hierarchy(), solver.links());
  // The grid links (GLNK) from the same gather, as Baker::Bake makes them.
  MakeGridLinks(core->mesh, solver.hierarchy(), core->gather, Hierarchical().grid_link_epsilon, &made);
  ASSERT_TRUE(made.has_grid_links());
  Baker baker(scene, Hierarchical());
  relight::Bake bake = baker.Bake();
  bake_test::ExpectHierarchiesEqual(bake.hierarchy, made);  // the baker is deterministic
  // The Baker handed its stored links to that bake (and freed its solver's
  // copy before the solves): a second whole bake is refused, not made empty.
  EXPECT_THROW(baker.Bake(), std::logic_error);
  TempDir dir;
  const relight::Bake read = WriteAndRead(bake, dir.File("cornell.rlb"));
  bake_test::ExpectHierarchiesEqual(read.hierarchy, made);

  const Hierarchy& h = solver.hierarchy();
  ASSERT_EQ(made.node_count(), h.nodes.size());
  const std::vector<uint32_t> patch_of_leaf = PatchOfLeaf(made, core->mesh);
  std::vector<double> leaves_under(made.node_count(), 0);  // children come after parents
  for (uint32_t k = made.node_count(); k-- > 0;) {
    if (h.nodes[k].leaf()) leaves_under[k] = 1;
    if (h.nodes[k].parent != kNoNode) leaves_under[h.nodes[k].parent] += leaves_under[k];
  }
  for (uint32_t k = 0; k < made.node_count(); ++k) {
    const HierarchyNode& n = h.nodes[k];
    EXPECT_EQ(made.node_surface[k], n.surface);
    EXPECT_EQ(made.node_corner_count[k], n.corner_count);
    // Each leaf's area rounds by at most half a Q32.32 step; inner nodes add them up.
    EXPECT_NEAR(std::ldexp(static_cast<double>(made.node_area[k]), -32), n.area_m2,
                std::ldexp(leaves_under[k], -33));
    if (n.leaf()) {
      EXPECT_EQ(patch_of_leaf[k], n.patch) << "node " << k;
    }
  }
  EXPECT_LE(made.link_count(), solver.links().size());
  EXPECT_GT(made.link_count(), 0.99 * static_cast<double>(solver.links().size()));
}

// The bar: leaf and vertex exitance of the stored-form solve within 0.1 % of
// peak of the baker's hierarchical solve of the same emission, per channel,
// for a luminaire's direct light and for an emitter on part of the ceiling.
TEST(StoredHierarchy, SolveFromTheBakeAloneMatchesTheBakersSolve) {
  const Scene scene = CornellWithLeanTo();
  Baker baker(scene, Hierarchical());
  TempDir dir;
  const relight::Bake bake = WriteAndRead(baker.Bake(), dir.File("cornell.rlb"));
  ASSERT_TRUE(bake.hierarchy.has_value());
  const BakeHierarchy& h = *bake.hierarchy;
  const auto core = BuildBakerCore(scene, Hierarchical(), nullptr);
  const Mesh& mesh = core->mesh;
  const HierarchicalSolver& solver = *core->hierarchical_solver;
  const std::vector<uint32_t> patch_of_leaf = PatchOfLeaf(h, mesh);
  const StoredSolve stored(bake);

  // Emission 1: the spot's direct light (100 cos^2 cd downwards from its
  // position), S = rho E per patch and channel as the baker computes it.
  const Eigen::VectorXd direct_lux = PatchIlluminance(
      core->direct[0], [](const Vec3& d) { return d[2] < 0 ? 100.0 * d[2] * d[2] : 0.0; });
  // Emission 2: 1000 lm/m^2 from the leaves under a grandchild of the
  // ceiling's root, as a run-time emitter covering that node would give.
  uint32_t ceiling_root = 0;
  while (bake.mesh.surface_names[h.node_surface[ceiling_root]] != "ceiling") ++ceiling_root;
  const uint32_t emitter = h.node_first_child[h.node_first_child[ceiling_root]];
  std::vector<bool> under(h.node_count(), false);
  under[emitter] = true;
  for (uint32_t k = emitter + 1; k < h.node_count(); ++k)
    under[k] = h.node_parent[k] != kBakeNoIndex && under[h.node_parent[k]];

  double worst_leaf = 0, worst_vertex = 0, worst_indirect = 0;
  for (const char* emission : {"spot", "ceiling emitter"}) {
    for (int c = 0; c < 3; ++c) {
      SCOPED_TRACE(std::string(emission) + ", channel " + std::to_string(c));
      Eigen::VectorXd s = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.patch_count()));
      std::vector<double> s_leaf(h.node_count(), 0);
      for (uint32_t k = 0; k < h.node_count(); ++k) {
        if (!h.leaf(k)) continue;
        const auto i = static_cast<Eigen::Index>(patch_of_leaf[k]);
        s(i) = emission[0] == 's' ? solver.reflectance(c)(i) * direct_lux(i)
                                  : (under[k] ? 1000.0 : 0.0);
        s_leaf[k] = s(i);
      }
      const Eigen::VectorXd want = solver.Solve(c, s);
      const std::vector<double> got_nodes = stored.Solve(c, s_leaf);
      std::vector<double> got(mesh.patch_count(), 0);
      for (uint32_t k = 0; k < h.node_count(); ++k)
        if (h.leaf(k)) got[patch_of_leaf[k]] = got_nodes[k];
      const double leaf_error = MaxOverPeak(got, want);
      const Eigen::MatrixXd want_vertices = AverageToVertices(mesh, want);
      const double vertex_error =
          MaxOverPeak(LeavesToVertices(bake, got_nodes), want_vertices.col(0));
      EXPECT_LT(leaf_error, 1e-3);
      EXPECT_LT(vertex_error, 1e-3);
      // The emission passes through unchanged; what the links carry is the
      // interreflected part, so hold the error against that part's peak too.
      const double indirect_peak = (want - s).cwiseAbs().maxCoeff();
      const double indirect_error = leaf_error * want.cwiseAbs().maxCoeff() / indirect_peak;
      EXPECT_GT(indirect_peak, 0.01 * want.cwiseAbs().maxCoeff());
      EXPECT_LT(indirect_error, 1e-3);
      worst_leaf = std::max(worst_leaf, leaf_error);
      worst_vertex = std::max(worst_vertex, vertex_error);
      worst_indirect = std::max(worst_indirect, indirect_error);
    }
  }
  std::printf("stored-hierarchy solve vs the baker's (%u nodes, %u links): leaf exitance within "
              "%.2e of peak, vertex exitance within %.2e of peak, leaf error %.2e of the "
              "interreflected light's peak\n",
              h.node_count(), h.link_count(), worst_leaf, worst_vertex, worst_indirect);
  RecordProperty("leaf_max_error_over_peak", std::to_string(worst_leaf));
  RecordProperty("vertex_max_error_over_peak", std::to_string(worst_vertex));
  RecordProperty("leaf_max_error_over_indirect_peak", std::to_string(worst_indirect));
}

}  // namespace
}  // namespace relight::baker
