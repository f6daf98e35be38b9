// The hierarchical solver against the dense (float64 LU) solve on the same
// mesh, surface by surface: no bias (the mean signed difference near 0 on
// every surface), mean |difference| <= 0.3 % and max <= 1 % of each
// surface's peak vertex luminance (docs/hierarchy.md, "Bias and its fix").
// The symptom was a bias: every surface of a grey room 0.1-0.4 %
// dark at these meshes (0.6-1.7 % at 0.1 m patches), from coarse links that
// took their source's mean exitance. The dense solve is computed here, not
// stored: the test measures, it does not compare against recorded numbers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "baker_core.h"
#include "reference.h"
#include "surface_agreement.h"

namespace relight::baker {
namespace {

// At the default link epsilon (1e-3) with the receiver-relative bound
// (BakeOptions::receiver_relative_links): with an absolute bound only, a dim
// wall reached 1.0-1.1 % at its worst vertex and 32 of the living room's 48
// surfaces were over the bar (docs/hierarchy.md, "Receiver-relative
// refinement"). signed_bound: the largest |mean signed difference| of one
// surface; the living room's shelf/+y sits at +0.19 % (measured, not fixed).
// also_absolute: also bake with the absolute bound alone and check it is
// far off on some surface (the receiver-relative bound is what helps, and
// the check above can fail); it reuses the dense solve.
void ExpectAgreement(const std::string& fixture, double signed_bound = 0.001,
                     bool also_absolute = false) {
  const Scene scene = LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/" + fixture);
  BakeOptions dense_options;
  dense_options.solver = SolverKind::kDense;
  BakeOptions hier_options;
  hier_options.solver = SolverKind::kHierarchical;
  const auto dense = BuildBakerCore(scene, dense_options, nullptr);
  const auto hier = BuildBakerCore(scene, hier_options, nullptr);
  std::vector<FixtureSetting> settings;
  for (const Luminaire& l : scene.luminaires)
    settings.push_back(FixtureSetting{l.pan_deg, l.tilt_deg, l.dimmer, l.colour});
  const ReferenceResult want = ComputeReference(*dense, settings);
  const ReferenceResult got = ComputeReference(*hier, settings);
  const auto surfaces =
      CompareBySurface(scene, dense->mesh, got.vertex_luminance, want.vertex_luminance);
  ASSERT_EQ(surfaces.size(), scene.surfaces.size());
  double sum_signed = 0;
  for (const SurfaceAgreement& a : surfaces) {
    ASSERT_GT(a.peak, 0) << a.name;
    EXPECT_LE(a.mean_abs, 0.003) << a.name;
    EXPECT_LE(a.max_abs, 0.01) << a.name;
    // A bias would put the signed mean near the mean |.|; noise keeps it small.
    EXPECT_LE(std::abs(a.mean_signed), signed_bound) << a.name;
    sum_signed += a.mean_signed;
    ::testing::Test::RecordProperty(a.name + "_mean_signed", std::to_string(a.mean_signed));
    ::testing::Test::RecordProperty(a.name + "_max_abs", std::to_string(a.max_abs));
  }
  // Over all surfaces: no sign shared by all of them.
  EXPECT_LE(std::abs(sum_signed / static_cast<double>(surfaces.size())), 5e-4);
  // The solve stopped on its residual, and says where.
  EXPECT_GT(hier->hierarchical_solver->max_residual(), 0);
  EXPECT_LE(hier->hierarchical_solver->max_residual(), hier_options.solve_tolerance);
  if (!also_absolute) return;
  BakeOptions absolute = hier_options;
  absolute.receiver_relative_links = false;
  const auto loose = BuildBakerCore(scene, absolute, nullptr);
  const ReferenceResult loose_got = ComputeReference(*loose, settings);
  double worst = 0;
  for (const SurfaceAgreement& a :
       CompareBySurface(scene, dense->mesh, loose_got.vertex_luminance, want.vertex_luminance))
    worst = std::max(worst, a.max_abs);
  EXPECT_GT(worst, 0.05);
  EXPECT_LT(loose->report.links, hier->report.links);
}

TEST(HierarchyBias, GreyRoomAgreesWithTheDenseSolvePerSurface) {
  ExpectAgreement("grey_room.toml");
}

TEST(HierarchyBias, CornellBoxAgreesWithTheDenseSolvePerSurface) {
  ExpectAgreement("cornell_box.toml");
}

// 48 surfaces, 2 715 patches: the sofa's faces in the 5 cm gap to the wall
// are 30-1000x dimmer than the room. With the absolute bound alone the sofa
// face in the gap is off by 91 % of its peak at its worst vertex.
TEST(HierarchyBias, LivingRoomAgreesWithTheDenseSolvePerSurface) {
  ExpectAgreement("living_room.toml", 0.002, /*also_absolute=*/true);
}

// The residual criterion: a tighter tolerance gives a smaller residual, and
// the stopping residual bounds the error against an exact solve of the same
// hierarchical operator (here: many more sweeps).
TEST(HierarchyBias, ResidualCriterionBoundsTheSolveError) {
  Scene scene = LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/grey_room.toml");
  scene.patch_size_m = 0.4;
  BakeOptions options;
  options.solver = SolverKind::kHierarchical;
  const auto core = BuildBakerCore(scene, options, nullptr);
  const Eigen::Index n = static_cast<Eigen::Index>(core->mesh.patch_count());
  const Eigen::MatrixXd e = Eigen::MatrixXd::Constant(n, 1, 100.0);
  std::vector<Rgb> rho;
  for (const Patch& p : core->mesh.patches) rho.push_back(p.reflectance);
  const HierarchicalSolver& loose = *core->hierarchical_solver;
  HierarchicalSolveOptions tight_options;
  tight_options.tolerance = 1e-10;
  const HierarchicalSolver tight(loose.hierarchy(), loose.links(), rho, tight_options);
  const Eigen::VectorXd m_loose = loose.SolveExitance(0, e);
  const Eigen::VectorXd m_tight = tight.SolveExitance(0, e);
  const double peak = m_tight.cwiseAbs().maxCoeff();
  EXPECT_LE((m_loose - m_tight).cwiseAbs().maxCoeff(), options.solve_tolerance * peak);
  EXPECT_LT(tight.max_residual(), loose.max_residual());
  EXPECT_LE(tight.max_residual(), 1e-10);
}

}  // namespace
}  // namespace relight::baker
