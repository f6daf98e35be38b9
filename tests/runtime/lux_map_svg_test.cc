// relight-probe --svg: the false-colour lux plan (runtime/tools/lux_map_svg.h).
#include "lux_map_svg.h"

#include <gtest/gtest.h>

#include <string>

namespace relight::cli {
namespace {

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The y attribute of the cell whose tooltip is `title`.
double CellY(const std::string& svg, const std::string& title) {
  const size_t t = svg.find("<title>" + title + "</title>");
  EXPECT_NE(t, std::string::npos) << title;
  const size_t rect = svg.rfind("<rect x=", t);
  const size_t y = svg.find("y=\"", rect);
  return std::stod(svg.substr(y + 3));
}

TEST(LuxMap, ScaleTopIsTheNextRoundNumber) {
  EXPECT_EQ(ScaleTop(0), 1);
  EXPECT_EQ(ScaleTop(0.3), 1);
  EXPECT_EQ(ScaleTop(1091), 1200);
  EXPECT_EQ(ScaleTop(2000), 2000);
  EXPECT_EQ(ScaleTop(2001), 2500);
  EXPECT_EQ(ScaleTop(7.5), 8);
}

TEST(LuxMap, ColoursRunFromBlueToRedAndClamp) {
  EXPECT_EQ(LuxColour(0, 500), "#141e78");
  EXPECT_EQ(LuxColour(500, 500), "#dc321e");
  EXPECT_EQ(LuxColour(900, 500), "#dc321e");
  EXPECT_EQ(LuxColour(-3, 500), "#141e78");
  EXPECT_NE(LuxColour(250, 500), LuxColour(260, 500));
}

TEST(LuxMap, SummaryGivesMinAverageMaxAndUniformity) {
  const LuxSummary s = Summarise({50, 100, 150});
  EXPECT_DOUBLE_EQ(s.min, 50);
  EXPECT_DOUBLE_EQ(s.avg, 100);
  EXPECT_DOUBLE_EQ(s.max, 150);
  EXPECT_DOUBLE_EQ(s.u0, 0.5);
  EXPECT_EQ(Summarise({0, 0}).u0, 0);
}

TEST(LuxMap, RectangleGridDrawsEveryCellRowZeroAtTheBottom) {
  GridLux g;
  g.name = "desk <A&B>";
  g.columns = 3;
  g.rows = 2;
  // 1 m spacing, x along columns, y along rows.
  for (unsigned r = 0; r < 2; ++r) {
    for (unsigned c = 0; c < 3; ++c) g.xyz_m.insert(g.xyz_m.end(), {1.0 * c, 1.0 * r, 0.75});
  }
  g.lux = {12.5, 20, 30, 400, 550, 612};
  const std::string svg = LuxMapSvg({g}, "test & check");
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  for (const char* title : {"12.5 lx", "20.0 lx", "30.0 lx", "400 lx", "550 lx", "612 lx"}) {
    EXPECT_EQ(Count(svg, std::string("<title>") + title + "</title>"), 1u) << title;
  }
  EXPECT_GT(CellY(svg, "12.5 lx"), CellY(svg, "400 lx"));  // row 0 drawn below row 1
  EXPECT_NE(svg.find("desk &lt;A&amp;B&gt;"), std::string::npos);
  EXPECT_EQ(svg.find("<A&B>"), std::string::npos);
  EXPECT_NE(svg.find("test &amp; check"), std::string::npos);
  EXPECT_NE(svg.find("Emin 12.5 lx"), std::string::npos);
  EXPECT_NE(svg.find("Emax 612 lx"), std::string::npos);
  EXPECT_NE(svg.find("U0 = Emin/Eavg 0.046"), std::string::npos);  // 12.5 / 270.75
  EXPECT_NE(svg.find(">800</text>"), std::string::npos);          // colour bar top: ScaleTop(612)
  EXPECT_NE(svg.find("3.00 m × 2.00 m"), std::string::npos);
}

TEST(LuxMap, PointListIsDrawnAsDots) {
  GridLux g;
  g.name = "seats";
  g.xyz_m = {0, 0, 1.2, 4, 3, 1.2};
  g.lux = {75, 300};
  const std::string svg = LuxMapSvg({g}, "list");
  EXPECT_EQ(Count(svg, "<circle"), 2u);
  EXPECT_NE(svg.find("<title>300 lx</title>"), std::string::npos);
}

}  // namespace
}  // namespace relight::cli
