// Hierarchical radiosity (quadtrees, BF-refined links, Gauss-Seidel with
// push-pull) against the dense solver on the same mesh, and against closed
// forms: the closed box B = E / (1 - rho), reciprocity and energy
// conservation of the links, and the living room within 1% of peak.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "test_scenes.h"
#include "baker_core.h"
#include "hierarchy.h"
#include "hierarchy_links.h"
#include "hierarchy_solve.h"
#include "link_brightness.h"
#include "luminaire_basis.h"
#include "radiosity_vec.h"
#include "reference.h"
#include "relight/baker/baker.h"
#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

// --- scenes -------------------------------------------------------------------

using namespace test_scenes;

// A room with a table (it shadows the floor), coloured surfaces, a spot and
// a grid: small enough for the dense solver, with occlusion and corners.
Scene Room(double patch_size_m) {
  Scene s;
  s.name = "room";
  s.path = "room.toml";
  s.patch_size_m = patch_size_m;
  s.surfaces = InwardBox({0, 0, 0}, {3, 2.5, 2.4}, {0.3, 0.25, 0.2}, {0.7, 0.6, 0.5},
                         {0.8, 0.8, 0.8});
  s.surfaces.push_back(Quad("table", {1, 1, 0.7}, {2, 1, 0.7}, {2, 1.6, 0.7}, {1, 1.6, 0.7},
                            {0.4, 0.3, 0.2}));
  s.surfaces.push_back(Quad("table under", {1, 1, 0.69}, {1, 1.6, 0.69}, {2, 1.6, 0.69},
                            {2, 1, 0.69}, {0.4, 0.3, 0.2}));
  // A sloping triangle leaning on the -x wall: a non-power-of-two triangle grid.
  s.surfaces.push_back(
      Triangle("lean-to", {0.01, 0.3, 0.0}, {0.9, 1.1, 0.0}, {0.01, 0.7, 1.2}, {0.6, 0.6, 0.6}));
  Luminaire l;
  l.name = "spot";
  l.position = {1.2, 1.1, 2.2};
  l.sh_degree = 3;
  l.use_sigma = false;
  l.lid.kind = LidKind::kCosPower;
  l.lid.exponent = 4;
  l.lid.spread_deg = 80;
  l.lid.peak_cd = 500;
  s.luminaires = {l};
  s.grids = {WorkplaneGrid()};
  return s;
}

std::unique_ptr<BakerCore> Core(const Scene& scene, SolverKind solver, double epsilon = 1e-3,
                                double tolerance = 1e-4) {
  BakeOptions options;
  options.solver = solver;
  options.link_epsilon = epsilon;
  options.solve_tolerance = tolerance;
  return BuildBakerCore(scene, options, nullptr);
}

double PolygonArea(const HierarchyNode& n) {
  Vec3 twice{0, 0, 0};
  for (int k = 0; k < n.corner_count; ++k)
    twice += Cross(n.corners[k], n.corners[(k + 1) % n.corner_count]);
  return 0.5 * Length(twice);
}

double MaxRelative(const std::vector<Rgb>& got, const std::vector<Rgb>& want, double* peak_out) {
  double peak = 0, worst = 0;
  for (size_t k = 0; k < want.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      peak = std::max(peak, std::abs(want[k][c]));
      worst = std::max(worst, std::abs(got[k][c] - want[k][c]));
    }
  }
  if (peak_out) *peak_out = peak;
  return worst / peak;
}

// --- the quadtrees ---------------------------------------------------------------

TEST(Hierarchy, LeavesAreThePatchesOnceAndNodesTileTheirSurface) {
  Scene scene;
  scene.patch_size_m = 0.1;
  scene.surfaces = {
      Quad("rectangle", {0, 0, 0}, {1, 0, 0}, {1, 0.7, 0}, {0, 0.7, 0}),  // 10 x 7
      Quad("trapezoid", {0, 0, 1}, {0.5, 0.2, 1}, {0.5, 0.8, 1}, {0, 1.1, 1}),
      Triangle("k5", {2, 0, 0}, {2.5, 0, 0}, {2, 0.4, 0}),   // k = 5
      Triangle("k8", {3, 0, 0}, {3.8, 0, 0}, {3, 0.7, 0}),   // k = 8
      Triangle("k1", {5, 0, 0}, {5.05, 0, 0}, {5, 0.05, 0}),  // a single patch
  };
  const Mesh mesh = BuildMesh(scene);
  const Hierarchy h = BuildHierarchy(mesh);
  ASSERT_EQ(h.surface_count(), scene.surfaces.size());
  std::vector<int> seen(mesh.patch_count(), 0);
  for (size_t s = 0; s < h.surface_count(); ++s) {
    double leaf_area = 0;
    for (uint32_t k = h.surface_begin[s]; k < h.surface_begin[s + 1]; ++k) {
      const HierarchyNode& n = h.nodes[k];
      EXPECT_EQ(n.surface, s);
      EXPECT_LE(n.corner_count, kMaxNodeCorners);
      // The polygon is exactly the union of its leaves.
      EXPECT_NEAR(PolygonArea(n), n.area_m2, 1e-9 * n.area_m2) << "node " << k;
      // Convex and counter-clockwise about the surface's normal.
      for (int c = 0; c < n.corner_count; ++c) {
        const Vec3& a = n.corners[c];
        const Vec3& b = n.corners[(c + 1) % n.corner_count];
        const Vec3& d = n.corners[(c + 2) % n.corner_count];
        EXPECT_GT(Dot(Cross(b - a, d - b), n.normal), 0) << "node " << k;
        EXPECT_GT(Dot(Cross(b - a, n.centre - a), n.normal), 0) << "centre outside node " << k;
      }
      if (n.leaf()) {
        ASSERT_NE(n.patch, kNoNode);
        ++seen[n.patch];
        EXPECT_EQ(h.leaf_of_patch[n.patch], k);
        leaf_area += n.area_m2;
        continue;
      }
      EXPECT_GE(n.child_count, 2u);
      EXPECT_LE(n.child_count, 4u);
      double children = 0;
      for (uint32_t c = n.first_child; c < n.first_child + n.child_count; ++c) {
        EXPECT_GT(c, k);  // parents before children
        EXPECT_EQ(h.nodes[c].parent, k);
        EXPECT_EQ(h.nodes[c].depth, n.depth + 1);
        children += h.nodes[c].area_m2;
      }
      EXPECT_NEAR(children, n.area_m2, 1e-12 * n.area_m2);
    }
    EXPECT_NEAR(leaf_area, h.nodes[h.root(s)].area_m2, 1e-12);
  }
  for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "patch " << i;
  // A 10 x 7 grid has a tree about log2(10) deep, not a flat list.
  EXPECT_LE(h.nodes[h.surface_begin[1] - 1].depth, 5u);
}

// --- links --------------------------------------------------------------------------

TEST(HierarchyLinks, ZeroEpsilonLinksEveryPatchPairWithTheDenseFactors) {
  const Scene scene = Room(0.5);
  const auto dense = Core(scene, SolverKind::kDense);
  const auto hier = Core(scene, SolverKind::kHierarchical, 0.0);
  const Hierarchy& h = hier->hierarchical_solver->hierarchy();
  size_t nonzero = 0;
  for (Eigen::Index i = 0; i < dense->form_factors.rows(); ++i)
    for (Eigen::Index j = i + 1; j < dense->form_factors.cols(); ++j)
      nonzero += dense->form_factors(i, j) > 0 || dense->form_factors(j, i) > 0;
  const auto& links = hier->hierarchical_solver->links();
  EXPECT_EQ(links.size(), nonzero);
  for (const HierarchyLink& l : links) {
    ASSERT_TRUE(h.nodes[l.p].leaf() && h.nodes[l.q].leaf());
    const auto i = static_cast<Eigen::Index>(h.nodes[l.p].patch);
    const auto j = static_cast<Eigen::Index>(h.nodes[l.q].patch);
    EXPECT_EQ(l.f_pq, dense->form_factors(i, j));
    EXPECT_EQ(l.f_qp, dense->form_factors(j, i));
  }
}

TEST(HierarchyLinks, DeterministicWhateverTheThreadCount) {
  const Scene scene = Room(0.25);
  const Mesh mesh = BuildMesh(scene);
  const Visibility vis(mesh, 1);
  const PatchSampleSets samples = BuildPatchSampleSets(mesh);
  const Hierarchy h = BuildHierarchy(mesh);
  const std::vector<double> brightness(h.nodes.size(), 1.0);
  const auto one = RefineLinks(mesh, vis, samples, h, brightness, 2e-3, false, 1, nullptr);
  const auto two = RefineLinks(mesh, vis, samples, h, brightness, 2e-3, false, 2, nullptr);
  ASSERT_EQ(one.size(), two.size());
  for (size_t k = 0; k < one.size(); ++k) {
    EXPECT_EQ(one[k].p, two[k].p);
    EXPECT_EQ(one[k].q, two[k].q);
    EXPECT_EQ(one[k].f_pq, two[k].f_pq);
    EXPECT_EQ(one[k].g_qp, two[k].g_qp);
  }
}

// Issue 16: a distributed bake refines each rank's share of the surface
// pairs; the shares together are exactly the one-process links (none lost,
// none twice, the same factors).
TEST(HierarchyLinks, SharesOverRanksAddUpToTheWhole) {
  const Scene scene = Room(0.25);
  const Mesh mesh = BuildMesh(scene);
  const Visibility vis(mesh, 1);
  const PatchSampleSets samples = BuildPatchSampleSets(mesh);
  const Hierarchy h = BuildHierarchy(mesh);
  const std::vector<double> brightness(h.nodes.size(), 1.0);
  const auto whole = RefineLinks(mesh, vis, samples, h, brightness, 2e-3, false, 2, nullptr);
  std::vector<HierarchyLink> shares;
  size_t smallest = whole.size();
  for (int rank = 0; rank < 3; ++rank) {
    const auto part =
        RefineLinks(mesh, vis, samples, h, brightness, 2e-3, false, 2, nullptr, rank, 3);
    smallest = std::min(smallest, part.size());
    shares.insert(shares.end(), part.begin(), part.end());
  }
  EXPECT_GT(smallest, 0u);  // every rank got work
  std::sort(shares.begin(), shares.end(), [](const HierarchyLink& x, const HierarchyLink& y) {
    return x.p != y.p ? x.p < y.p : x.q < y.q;
  });
  ASSERT_EQ(shares.size(), whole.size());
  for (size_t k = 0; k < whole.size(); ++k) {
    EXPECT_EQ(shares[k].p, whole[k].p);
    EXPECT_EQ(shares[k].q, whole[k].q);
    EXPECT_EQ(shares[k].f_pq, whole[k].f_pq);
    EXPECT_EQ(shares[k].f_qp, whole[k].f_qp);
    EXPECT_EQ(shares[k].g_pq, whole[k].g_pq);
  }
}

// Per leaf, the total fraction of its light that the links deliver
// elsewhere in a closed box (each ancestor's links, with their gradients
// evaluated at the leaf's centre): 1 for an exact operator. Returns the
// extremes over the leaves; *reciprocity: the worst |A_p F_pq - A_q F_qp| /
// max of the two over links, *weighted: its mean weighted by A_p F_pq.
void ClosedBoxRowSums(double epsilon, double* lo, double* hi, double* reciprocity,
                      double* weighted, size_t* link_count) {
  const auto core = Core(ClosedBox(0.05, {0.5, 0.5, 0.5}), SolverKind::kHierarchical, epsilon);
  const HierarchicalSolver& solver = *core->hierarchical_solver;
  const Hierarchy& h = solver.hierarchy();
  const auto& links = solver.links();
  *link_count = links.size();
  std::vector<std::vector<std::pair<double, std::array<double, 2>>>> gathers(h.nodes.size());
  double flux = 0, error = 0;
  *reciprocity = 0;
  for (const HierarchyLink& l : links) {
    gathers[l.p].push_back({l.f_pq, l.g_pq});
    gathers[l.q].push_back({l.f_qp, l.g_qp});
    const double a = h.nodes[l.p].area_m2 * l.f_pq, b = h.nodes[l.q].area_m2 * l.f_qp;
    *reciprocity = std::max(*reciprocity, std::abs(a - b) / std::max(a, b));
    flux += a;
    error += std::abs(a - b);
  }
  *weighted = error / flux;
  *lo = 2;
  *hi = 0;
  for (size_t i = 0; i < core->mesh.patch_count(); ++i) {
    const uint32_t leaf = h.leaf_of_patch[i];
    const Vec3& x = h.nodes[leaf].centre;
    double sum = 0;
    for (uint32_t a = leaf; a != kNoNode; a = h.nodes[a].parent) {
      const auto xa = h.PlaneCoords(h.nodes[a].surface, x);
      const auto ca = h.PlaneCoords(h.nodes[a].surface, h.nodes[a].centre);
      for (const auto& [f, g] : gathers[a])
        sum += f + g[0] * (xa[0] - ca[0]) + g[1] * (xa[1] - ca[1]);
    }
    *lo = std::min(*lo, sum);
    *hi = std::max(*hi, sum);
  }
}

TEST(HierarchyLinks, ClosedBoxRowsSumToOneAndLinksAreReciprocal) {
  // Measured: rows 0.977..1.023 at epsilon 1e-3 (68836 links), 0.9964..1.0028
  // at 1e-4 (1.2 million; the dense matrix has 5.8 million entries); the
  // links' reciprocity error is 0.45% weighted by flux, 4.2% at worst.
  double lo, hi, reciprocity, weighted;
  size_t coarse_links, fine_links;
  ClosedBoxRowSums(1e-3, &lo, &hi, &reciprocity, &weighted, &coarse_links);
  EXPECT_NEAR(lo, 1.0, 0.03);
  EXPECT_NEAR(hi, 1.0, 0.03);
  EXPECT_LT(weighted, 0.01);
  EXPECT_LT(reciprocity, 0.06);
  RecordProperty("row_sum_range_eps_1e-3", std::to_string(lo) + ".." + std::to_string(hi));
  // Refinement converges: a smaller epsilon, more links, exact rows.
  ClosedBoxRowSums(1e-4, &lo, &hi, &reciprocity, &weighted, &fine_links);
  EXPECT_GT(fine_links, 4 * coarse_links);
  EXPECT_NEAR(lo, 1.0, 0.005);
  EXPECT_NEAR(hi, 1.0, 0.005);
  RecordProperty("row_sum_range_eps_1e-4", std::to_string(lo) + ".." + std::to_string(hi));
}

TEST(LinkBrightness, NoLuminairesMeansPlainFormFactorRefinement) {
  const Scene scene = ClosedBox(0.5, {0.5, 0.5, 0.5});
  const Mesh mesh = BuildMesh(scene);
  const Hierarchy h = BuildHierarchy(mesh);
  for (double b : RefinementBrightness(scene, mesh, h, {})) EXPECT_EQ(b, 1.0);
}

// --- the solve ----------------------------------------------------------------------------

TEST(HierarchicalSolver, ClosedBoxUniformEmissionGivesEOverOneMinusRho) {
  const Rgb rho{0.3, 0.5, 0.8};
  for (double epsilon : {1e-3, 1e-4}) {
    const auto core = Core(ClosedBox(0.05, rho), SolverKind::kHierarchical, epsilon, 1e-6);
    const HierarchicalSolver& solver = *core->hierarchical_solver;
    const Eigen::Index n = static_cast<Eigen::Index>(core->mesh.patch_count());
    const double e = 10.0;
    // The rows' error (above) grows by rho / (1 - rho) through the bounces.
    const double tolerance = epsilon > 5e-4 ? 0.03 : 0.01;
    for (int c = 0; c < 3; ++c) {
      const Eigen::VectorXd m = solver.Solve(c, Eigen::VectorXd::Constant(n, e));
      const double expected = e / (1 - rho[c]);
      EXPECT_NEAR(m.minCoeff(), expected, tolerance * expected) << "channel " << c;
      EXPECT_NEAR(m.maxCoeff(), expected, tolerance * expected) << "channel " << c;
    }
    // All channels at once, illuminance form: uniform E gives rho E / (1 - rho).
    const auto m = solver.SolveExitanceRgb(Eigen::MatrixXd::Constant(n, 2, e));
    for (int c = 0; c < 3; ++c) {
      const double expected = rho[c] * e / (1 - rho[c]);
      EXPECT_NEAR(m[c].minCoeff(), expected, tolerance * expected) << "channel " << c;
      EXPECT_NEAR(m[c].maxCoeff(), expected, tolerance * expected) << "channel " << c;
    }
    EXPECT_GT(solver.max_sweeps_used(), 2);
  }
}

TEST(HierarchicalSolver, ZeroEpsilonReproducesTheDenseSolve) {
  const Scene scene = Room(0.5);
  const auto dense = Core(scene, SolverKind::kDense);
  const auto hier = Core(scene, SolverKind::kHierarchical, 0.0, 1e-10);
  const LuminaireBasis want = ComputeLuminaireBasis(*dense, 0, DirectModeKind::kAllInSh);
  const LuminaireBasis got = ComputeLuminaireBasis(*hier, 0, DirectModeKind::kAllInSh);
  for (size_t set = 0; set < want.sets.size(); ++set) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::MatrixXd& w = want.sets[set].basis[c];
      const double peak = w.cwiseAbs().maxCoeff();
      EXPECT_LT((got.sets[set].basis[c] - w).cwiseAbs().maxCoeff(), 1e-7 * peak)
          << "set " << set << " channel " << c;
    }
  }
}

// The bar: vertex luminances within 1% of peak of the dense solver's,
// on the living-room fixture meshed coarsely enough for both (1568 patches).
TEST(HierarchicalSolver, LivingRoomWithinOnePercentOfPeakOfTheDenseSolver) {
  Scene scene = LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/living_room.toml");
  scene.patch_size_m = 0.3;
  const auto dense = Core(scene, SolverKind::kDense);
  const auto hier = Core(scene, SolverKind::kHierarchical, BakeOptions().link_epsilon,
                         BakeOptions().solve_tolerance);
  std::vector<FixtureSetting> settings;
  for (const Luminaire& l : scene.luminaires)
    settings.push_back(FixtureSetting{l.pan_deg, l.tilt_deg, l.dimmer, l.colour});
  std::vector<FixtureSetting> turned = settings;
  for (FixtureSetting& s : turned) {
    s.pan_deg = 45;
    s.tilt_deg = 60;
  }
  for (const auto& [label, s] : {std::pair<const char*, std::vector<FixtureSetting>>{
                                     "defaults", settings},
                                 {"pan45_tilt60", turned}}) {
    const ReferenceResult want = ComputeReference(*dense, s);
    const ReferenceResult got = ComputeReference(*hier, s);
    double peak = 0;
    const double vertex_err = MaxRelative(got.vertex_luminance, want.vertex_luminance, &peak);
    const double patch_err = MaxRelative(got.vertex_luminance_patch_average,
                                         want.vertex_luminance_patch_average, nullptr);
    EXPECT_LT(vertex_err, 0.01) << label;
    EXPECT_LT(patch_err, 0.01) << label;
    EXPECT_GT(peak, 10.0);
    RecordProperty(std::string("vertex_max_rel_error_") + label, std::to_string(vertex_err));
  }
}

// --- the baker ------------------------------------------------------------------------------

// Bake() and Reference() go through the same (hierarchical) solver: with a
// beam that degree 3 represents exactly, 100 (1 + cos g + cos^2 g) cd =
// sum_l w_l P_l(cos g), w = 100 {4/3, 1, 2/3, 0}, the recombined basis
// equals the reference up to the sweeps' tolerance.
TEST(HierarchicalBake, BasisRecombinesToTheReferenceOfTheSameSolver) {
  Scene scene = Room(0.25);
  Luminaire& lum = scene.luminaires[0];
  lum.lid = Lid{};
  lum.lid.kind = LidKind::kTable;
  for (int k = 0; k <= 18000; ++k) {
    const double c = std::cos(k * 0.01 * 3.14159265358979323846 / 180);
    lum.lid.gamma_deg.push_back(k * 0.01);
    lum.lid.candela.push_back(100 * (1 + c + c * c));
  }
  const std::vector<double> legendre = {100 * 4.0 / 3.0, 100, 100 * 2.0 / 3.0, 0};
  BakeOptions options;
  options.solver = SolverKind::kHierarchical;
  options.solve_tolerance = 1e-8;
  options.direct_mode = DirectModeKind::kAllInSh;
  Baker baker(scene, options);
  const auto core = BuildBakerCore(scene, options, nullptr);
  const LuminaireBasis basis = ComputeLuminaireBasis(*core, 0, DirectModeKind::kAllInSh);
  const FixtureSetting setting{30, 40, 0.7, {1, 0.6, 0.3}};
  const ReferenceResult ref = baker.Reference({setting});
  const std::vector<double> w =
      TermWeights(legendre, BeamAxis(lum.mounting, setting.pan_deg, setting.tilt_deg), false);
  std::vector<Rgb> recombined(ref.vertex_luminance_patch_average.size(), Rgb{0, 0, 0});
  for (size_t v = 0; v < recombined.size(); ++v) {
    for (int c = 0; c < 3; ++c) {
      for (size_t t = 0; t < w.size(); ++t) {
        recombined[v][c] += w[t] * basis.sets[0].basis[c](static_cast<Eigen::Index>(v),
                                                          static_cast<Eigen::Index>(t));
      }
      recombined[v][c] *= setting.dimmer * setting.colour[c];
    }
  }
  EXPECT_LT(MaxRelative(recombined, ref.vertex_luminance_patch_average, nullptr), 1e-5);
  EXPECT_EQ(baker.report().solver, SolverKind::kHierarchical);
  EXPECT_GT(baker.report().links, 0u);
  EXPECT_GT(baker.report().nodes, core->mesh.patch_count());
}

TEST(HierarchicalBake, AutoPicksDenseForSmallScenesAndHierarchicalForLarge) {
  EXPECT_EQ(Core(ClosedBox(0.25, {0.5, 0.5, 0.5}), SolverKind::kAuto)->solver_kind,
            SolverKind::kDense);
  const auto big = Core(ClosedBox(0.035, {0.5, 0.5, 0.5}), SolverKind::kAuto, 2e-2);
  EXPECT_GT(big->mesh.patch_count(), kAutoDenseMaxPatches);
  EXPECT_EQ(big->solver_kind, SolverKind::kHierarchical);
  EXPECT_EQ(big->form_factors.size(), 0);  // no n^2 matrix
  // The dense solver keeps its limit, and says what to do about it.
  try {
    Core(ClosedBox(0.006, {0.5, 0.5, 0.5}), SolverKind::kDense);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("hierarchical"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace relight::baker
