// Issue 17, scenes: a mesh too large to count in an int and a scene with no
// luminaire are clear errors naming the file (and line), never undefined
// behaviour or a "successful" empty bake.
#include <gtest/gtest.h>

#include <string>

#include "mesher.h"
#include "relight/baker/baker.h"
#include "relight/baker/scene.h"
#include "test_scenes.h"

namespace relight::baker {
namespace {

std::string Fixture(const std::string& name) {
  return std::string(RELIGHT_SOURCE_DIR) + "/fixtures/malformed/" + name;
}

template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const SceneError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST(HostileScene, HugeSurfaceSaysTheMeshWouldBeTooLarge) {
  const Scene scene = LoadScene(Fixture("huge_patch_count.toml"));
  for (const size_t limit : {kMaxDensePatches, kMaxHierarchicalPatches}) {
    const std::string what = ErrorOf([&] { BuildMesh(scene, limit); });
    EXPECT_EQ(what.rfind(Fixture("huge_patch_count.toml") + ":12: surface 'floor': the mesh "
                         "would be too large: patch_size 0.001 m cuts it into 1e+30 patches",
                         0),
              0u)
        << what;
    EXPECT_NE(what.find("more than the limit of " + std::to_string(limit) + " patches"),
              std::string::npos)
        << what;
  }
  // The baker stops at the same place, before any form factor.
  const std::string what = ErrorOf([&] { Baker baker(scene, BakeOptions{}); });
  EXPECT_NE(what.find("the mesh would be too large"), std::string::npos) << what;
}

TEST(HostileScene, TinyPatchSizeOverflowsNoCount) {
  // 1 / 1e-300 per side: the count is infinite in double, far past int.
  Scene scene = test_scenes::ClosedBox(1e-300, {0.5, 0.5, 0.5});
  const std::string what = ErrorOf([&] { BuildMesh(scene, kMaxHierarchicalPatches); });
  EXPECT_NE(what.find("surface 'floor': the mesh would be too large"), std::string::npos) << what;
  EXPECT_NE(what.find("inf patches"), std::string::npos) << what;
  // Just over the limit on the first surface: 142 x 142 = 20164 > 20000.
  scene = test_scenes::ClosedBox(1.0 / 141.5, {0.5, 0.5, 0.5});
  const std::string over = ErrorOf([&] { BuildMesh(scene, kMaxDensePatches); });
  EXPECT_NE(over.find("cuts it into 2.016e+04 patches, 0 before it"), std::string::npos) << over;
}

TEST(HostileScene, NoLuminairesIsNothingToBake) {
  const std::string path = Fixture("no_luminaires.toml");
  const Scene scene = LoadScene(path);
  ASSERT_TRUE(scene.luminaires.empty());
  BakeOptions dense;
  dense.solver = SolverKind::kDense;
  BakeOptions no_links;
  no_links.store_hierarchy = false;
  for (const BakeOptions& options : {dense, no_links, BakeOptions{}}) {
    const std::string what = ErrorOf([&] { Baker(scene, options).Bake(); });
    EXPECT_EQ(what.rfind(path + ": the scene has no luminaires: nothing to bake", 0), 0u) << what;
  }
  // A hierarchical bake keeping its links is for run-time surface emitters:
  // it needs no luminaire, and solves nothing with empty matrices.
  BakeOptions links;
  links.solver = SolverKind::kHierarchical;
  const relight::Bake bake = Baker(scene, links).Bake();
  EXPECT_TRUE(bake.luminaires.empty());
  EXPECT_TRUE(bake.hierarchy.has_value());
}

}  // namespace
}  // namespace relight::baker
