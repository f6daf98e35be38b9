// Issue 16: how a distributed bake shares the luminaires (the right-hand
// sides) out over ranks: every luminaire once, the same answer every time,
// the SH terms balanced as the greedy rule promises.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "relight/base/sh_index.h"
#include "relight/baker/distributed.h"

namespace relight::baker {
namespace {

Scene WithDegrees(const std::vector<int>& degrees) {
  Scene scene;
  for (size_t k = 0; k < degrees.size(); ++k) {
    Luminaire l;
    l.name = "l" + std::to_string(k);
    l.sh_degree = degrees[k];
    scene.luminaires.push_back(l);
  }
  return scene;
}

std::vector<int> Load(const Scene& scene, const std::vector<int>& owner, int ranks) {
  std::vector<int> load(static_cast<size_t>(ranks), 0);
  for (size_t l = 0; l < owner.size(); ++l)
    load[static_cast<size_t>(owner[l])] += ShTermCount(scene.luminaires[l].sh_degree);
  return load;
}

TEST(LuminaireShare, OneRankTakesEverything) {
  const Scene scene = WithDegrees({5, 8, 5});
  EXPECT_EQ(ShareLuminaires(scene, 1), (std::vector<int>{0, 0, 0}));
}

TEST(LuminaireShare, LargestFirstToTheLeastLoadedRank) {
  // The living room: 36, 81, 36 terms. Two ranks: 81 | 36 + 36.
  const Scene scene = WithDegrees({5, 8, 5});
  EXPECT_EQ(ShareLuminaires(scene, 2), (std::vector<int>{1, 0, 1}));
  // More ranks than luminaires: the last rank has none.
  EXPECT_EQ(ShareLuminaires(scene, 4), (std::vector<int>{1, 0, 2}));
}

TEST(LuminaireShare, FortyEightHeadsBalanceWithinOneLuminaire) {
  std::vector<int> degrees;
  for (int k = 0; k < 48; ++k) degrees.push_back(k % 3 == 0 ? 8 : (k % 3 == 1 ? 5 : 3));
  const Scene scene = WithDegrees(degrees);
  for (int ranks : {2, 3, 4, 7}) {
    const std::vector<int> owner = ShareLuminaires(scene, ranks);
    ASSERT_EQ(owner.size(), degrees.size());
    for (int o : owner) {
      EXPECT_GE(o, 0);
      EXPECT_LT(o, ranks);
    }
    EXPECT_EQ(owner, ShareLuminaires(scene, ranks));  // deterministic
    const std::vector<int> load = Load(scene, owner, ranks);
    const int spread = *std::max_element(load.begin(), load.end()) -
                       *std::min_element(load.begin(), load.end());
    EXPECT_LE(spread, ShTermCount(8)) << ranks << " ranks";
  }
}

}  // namespace
}  // namespace relight::baker
