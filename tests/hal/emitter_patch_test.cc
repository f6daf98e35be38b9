// [[emitter]] in a patch (issue 15): parsed into numbers, appended after the
// luminaires by ResolvePatch so every input addresses it as a fixture, its
// x, y and size decoded from registers as 16-bit levels; errors name
// file:line.
#include <gtest/gtest.h>

#include <string>

#include "relight/hal/mock_source.h"
#include "relight/hal/param_text.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal {
namespace {

const char* kPanel = R"([[fixture]]
name = "spot"

[[emitter]]
name = "panel"
surface = "room/+x"
centre = [6.0, 2.2, 1.5]
width = 1.2
height = 0.9
luminance = [2500, 2400, 2200]
x_range_m = [-1.5, 0.5]
y_range_m = [-0.4, 0.4]
size_range = [0.5, 1.0]
colour = [1, 0.5, 0]
fade_ms = 100

[[emitter]]
name = "window"
surface = "room/+y"
polygon = [[1, 4.5, 1], [2, 4.5, 1], [2, 4.5, 2]]
luminance = 800
dimmer = 0
registers = ["dimmer", "x"]
modbus_base = 200

[[gpio_button]]
chip = "gpiochip0"
line = 4
fixture = "window"
)";

TEST(EmitterPatch, ParsesRectangleAndPolygon) {
  Patch p;
  const Status st = ParsePatch(kPanel, "e.toml", &p);
  ASSERT_TRUE(st.ok()) << st.ToString();
  ASSERT_EQ(p.emitters.size(), 2u);
  const EmitterPatch& panel = p.emitters[0];
  EXPECT_EQ(panel.control.name, "panel");
  EXPECT_EQ(panel.control.line, 4);
  EXPECT_EQ(panel.control.emitter, 0);
  EXPECT_EQ(panel.surface, "room/+x");
  EXPECT_EQ(panel.centre_q16[0], 6 << 16);
  EXPECT_EQ(panel.width_q16, 78643);  // 1.2 m
  EXPECT_TRUE(panel.polygon_q16.empty());
  EXPECT_EQ(panel.luminance_q12[0], 2500 * 4096);
  EXPECT_EQ(panel.luminance_q12[2], 2200 * 4096);
  EXPECT_EQ(panel.x_range_q16[0], -98304);
  // Starts at offset 0: x = 1.5 / 2 of its range, y in the middle, size 1 = the top of 0.5..1.
  EXPECT_EQ(panel.x_q15, 24575);
  EXPECT_EQ(panel.y_q15, 16383);
  EXPECT_EQ(panel.size_q15, 32767);
  EXPECT_EQ(panel.dimmer_q15, 32767);
  EXPECT_EQ(panel.rgb_q15[1], 16384);
  EXPECT_EQ(panel.control.fade_ms, 100);
  EXPECT_EQ(panel.control.layout.size(), 7);  // dimmer, x, y, size, r, g, b
  EXPECT_EQ(panel.control.layout.OffsetOf(Channel::kSize), 3);
  const EmitterPatch& window = p.emitters[1];
  EXPECT_EQ(window.polygon_q16.size(), 3u);
  EXPECT_EQ(window.luminance_q12[1], 800 * 4096);
  EXPECT_EQ(window.dimmer_q15, 0);
  EXPECT_EQ(window.size_q15, 32767);  // no size range: scale 1
  EXPECT_EQ(window.control.layout.size(), 2);
}

TEST(EmitterPatch, ResolveAppendsEmittersAsFixturesAndRegistersDecodeThem) {
  Patch p;
  ASSERT_TRUE(ParsePatch(kPanel, "e.toml", &p).ok());
  const Status st = ResolvePatch({{"spot"}}, &p);  // the button names an emitter: fine
  ASSERT_TRUE(st.ok()) << st.ToString();
  ASSERT_EQ(p.fixtures.size(), 3u);
  EXPECT_EQ(p.fixtures[0].emitter, -1);
  EXPECT_EQ(p.fixtures[1].name, "panel");
  EXPECT_EQ(p.fixtures[1].emitter, 0);
  EXPECT_EQ(p.fixtures[2].emitter, 1);
  EXPECT_EQ(p.fixtures[2].modbus_base, 200);
  EXPECT_EQ(p.fixtures[0].modbus_base, 202);  // after the highest explicit block (the window's)
  EXPECT_EQ(p.fixtures[1].modbus_base, 210);  // after the spot's standard 8

  RegisterMap map;
  ASSERT_TRUE(RegisterMap::Build(p.fixtures, &map).ok());
  MockSource mock(p, std::vector<uint16_t>(static_cast<size_t>(map.holding_count()), 0));
  ASSERT_TRUE(mock.Start().ok());
  EXPECT_EQ(mock.SetHoldingRegister(210 + 1, 65535, 10), 0);  // panel x
  EXPECT_EQ(mock.SetHoldingRegister(210 + 3, 32768, 10), 0);  // panel size
  EXPECT_EQ(mock.SetHoldingRegister(200, 65535, 10), 0);    // window dimmer
  ParamChange out[8];
  const size_t n = mock.Poll(20, out, 8);
  ASSERT_EQ(n, 3u);
  EXPECT_EQ(out[0].fixture, 1);
  EXPECT_EQ(out[0].param, Param::kX);
  EXPECT_EQ(out[0].level.raw(), 32767);
  EXPECT_EQ(out[1].param, Param::kSize);
  EXPECT_EQ(out[1].level.raw(), LevelQ15FromRegister16(32768));
  EXPECT_EQ(out[2].fixture, 2);
  EXPECT_EQ(out[2].param, Param::kDimmer);

  // Replay text: x, y and size are levels 0..1.
  NamedChange parsed[3];
  std::string error;
  ASSERT_EQ(ParseParamText("panel.x=0.25", 0, parsed, &error), 1) << error;
  EXPECT_EQ(parsed[0].change.param, Param::kX);
  EXPECT_EQ(parsed[0].change.level.raw(), 8192);
  EXPECT_EQ(ParseParamText("panel.size=1.5", 0, parsed, &error), 0);
  EXPECT_NE(error.find("size must be in 0..1"), std::string::npos) << error;
}

TEST(EmitterPatch, ErrorsNameFileLine) {
  struct Case {
    const char* text;
    const char* line;
    const char* says;
  };
  const std::string head = "[[emitter]]\nname = \"e\"\nsurface = \"room/+z\"\nluminance = 100\n";
  const Case cases[] = {
      {"centre = [1, 1, 2.7]\nwidth = 1\n", "p.toml:1", "needs 'width' and 'height'"},
      {"centre = [1, 1, 2.7]\nwidth = 1\nheight = 1\npolygon = [[0,0,0],[1,0,0],[1,1,0]]\n", "p.toml:1",
       "not both"},
      {"width = 1\n", "p.toml:1", "not neither"},
      {"centre = [1, 1]\nwidth = 1\nheight = 1\n", "p.toml:5", "'centre' must be [x, y, z] in metres"},
      {"polygon = [[0,0,0],[1,0,0]]\n", "p.toml:5", "3..8 corners, got 2"},
      {"polygon = [[0,0,0],[1,0,0],[1,\"a\",0]]\n", "p.toml:5", "each polygon corner"},
      {"centre = [1, 1, 2.7]\nwidth = 0\nheight = 1\n", "p.toml:6", "'width' must be in 0.001..100 m"},
      {"centre = [1, 1, 2.7]\nwidth = 1\nheight = 1\nx_range_m = [0, 200]\n", "p.toml:8",
       "'x_range_m' must be [from, to], each in -100..100 m"},
      {"centre = [1, 1, 2.7]\nwidth = 1\nheight = 1\nsize_range = [0, 1]\n", "p.toml:8", "0.01..100"},
      {"centre = [1, 1, 2.7]\nwidth = 1\nheight = 1\npan = 3\n", "p.toml:8", "unknown key 'pan'"},
      {"centre = [1, 1, 2.7]\nwidth = 1\nheight = 1\nx = 2\n", "p.toml:8", "'x' must be in 0..1"},
      {"centre = [1, 1, 2.7]\nwidth = 1\nheight = 1\nregisters = [\"dimmer\", \"zap\"]\n", "p.toml:8",
       "unknown channel 'zap'"},
  };
  for (const Case& c : cases) {
    Patch p;
    const std::string text = head + c.text;
    const Status st = ParsePatch(text, "p.toml", &p);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << text;
    EXPECT_NE(st.message().find(c.line), std::string::npos) << text << " -> " << st.message();
    EXPECT_NE(st.message().find(c.says), std::string::npos) << text << " -> " << st.message();
  }
  Patch p;
  const std::string lum_missing = "[[emitter]]\nname = \"e\"\nsurface = \"s\"\ncentre = [1,1,1]\nwidth = 1\nheight = 1\n";
  EXPECT_NE(ParsePatch(lum_missing, "p.toml", &p).message().find("p.toml:1: emitter 1: missing 'luminance'"),
            std::string::npos);
  const std::string twice = head + "centre = [1,1,2.7]\nwidth = 1\nheight = 1\n" + head +
                            "centre = [1,1,2.7]\nwidth = 1\nheight = 1\n";
  EXPECT_NE(ParsePatch(twice, "p.toml", &p).message().find("p.toml:8: emitter 2: emitter 'e' is patched twice"),
            std::string::npos)
      << ParsePatch(twice, "p.toml", &p).message();
  // A name a luminaire has already.
  ASSERT_TRUE(ParsePatch(head + "centre = [1,1,2.7]\nwidth = 1\nheight = 1\n", "p.toml", &p).ok());
  const Status clash = ResolvePatch({{"e"}}, &p);
  EXPECT_EQ(clash.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(clash.message().find("p.toml:1: emitter 'e': the bake has a luminaire of that name"), std::string::npos)
      << clash.message();
  // Nine emitters: more than the engine holds.
  std::string nine;
  for (int i = 0; i < 9; ++i) {
    nine += "[[emitter]]\nname = \"e" + std::to_string(i) +
            "\"\nsurface = \"s\"\nluminance = 1\ncentre = [1,1,1]\nwidth = 1\nheight = 1\n";
  }
  EXPECT_NE(ParsePatch(nine, "p.toml", &p).message().find("more than 8 emitters"), std::string::npos);
}

}  // namespace
}  // namespace relight::hal
