#include <gtest/gtest.h>

#include <string>

#include "relight/hal/patch.h"

namespace relight::hal {
namespace {

const char* kFullPatch = R"(# a patch with every section
[[fixture]]
name = "spot"
modbus_base = 16
pan_range_deg = 540
tilt_range_deg = 270
dimmer_curve = "square"
fade_ms = 250

[[fixture]]
name = "wash"

[modbus_tcp]
listen = "127.0.0.1"
port = 0
allow = ["127.0.0.1", "10.0.0.7"]
max_clients = 4
idle_timeout_ms = 5000
request_timeout_ms = 1500

[modbus_rtu]
device = "/dev/ttyUSB0"
baud = 38400
parity = "even"
unit_id = 7

[modbus_poller]
host = "127.0.0.1"
port = 5020
rate_hz = 20
map = [ { register = 100, fixture = "wash", param = "dimmer" },
        { register = 103, fixture = "wash", param = "r" } ]

[[gpio_button]]
chip = "gpiochip0"
line = 17
fixture = "spot"
on_level = 0.5

[[gpio_button]]
chip = "gpiochip0"
line = 18
action = "preset"
preset = ["spot.pan=30", "wash.colour=1,0.5,0"]

[[gpio_encoder]]
chip = "gpiochip1"
line_a = 3
line_b = 4
fixture = "wash"
param = "tilt"
step = 0.5

[replay]
script = "show.replay"
)";

TEST(Patch, ParsesEverySection) {
  Patch p;
  const Status st = ParsePatch(kFullPatch, "full.toml", &p);
  ASSERT_TRUE(st.ok()) << st.ToString();
  ASSERT_EQ(p.fixtures.size(), 2u);
  EXPECT_EQ(p.fixtures[0].name, "spot");
  EXPECT_EQ(p.fixtures[0].modbus_base, 16);
  EXPECT_EQ(p.fixtures[0].pan_range_q16, 540 << 16);
  EXPECT_EQ(p.fixtures[0].dimmer_curve, DimmerCurve::kSquare);
  EXPECT_EQ(p.fixtures[0].fade_ms, 250);
  EXPECT_EQ(p.fixtures[1].modbus_base, -1);
  EXPECT_EQ(p.fixtures[1].tilt_range_q16, 0);  // not given: the luminaire's, at resolve
  EXPECT_TRUE(p.modbus_tcp.enabled);
  EXPECT_EQ(p.modbus_tcp.port, 0);
  EXPECT_EQ(p.modbus_tcp.allow.size(), 2u);
  EXPECT_EQ(p.modbus_tcp.max_clients, 4);
  EXPECT_EQ(p.modbus_tcp.idle_timeout_ms, 5000);
  EXPECT_EQ(p.modbus_tcp.request_timeout_ms, 1500);
  EXPECT_TRUE(p.modbus_rtu.enabled);
  EXPECT_EQ(p.modbus_rtu.parity, 'E');
  EXPECT_EQ(p.modbus_rtu.unit_id, 7);
  EXPECT_EQ(p.modbus_poller.map.size(), 2u);
  EXPECT_EQ(p.modbus_poller.map[1].channel, Channel::kRed);
  ASSERT_EQ(p.buttons.size(), 2u);
  EXPECT_EQ(p.buttons[0].on_level_q15, 16384);
  EXPECT_EQ(p.buttons[1].action, ButtonAction::kPreset);
  EXPECT_EQ(p.buttons[1].preset.size(), 4u);  // pan + three colour changes
  ASSERT_EQ(p.encoders.size(), 1u);
  EXPECT_EQ(p.encoders[0].step, 32768);  // 0.5 degree in Q16.16
  EXPECT_EQ(p.replay_script, "show.replay");
}

TEST(Patch, ResolveAddsUnpatchedLuminairesAndAssignsBlocks) {
  Patch p;
  ASSERT_TRUE(ParsePatch(kFullPatch, "full.toml", &p).ok());
  ASSERT_TRUE(ResolvePatch({{"wash"}, {"spot"}, {"uplight"}}, &p).ok());
  ASSERT_EQ(p.fixtures.size(), 3u);
  EXPECT_EQ(p.fixtures[0].modbus_base, 16);  // explicit
  EXPECT_EQ(p.fixtures[1].modbus_base, 24);  // after the highest explicit block
  EXPECT_EQ(p.fixtures[2].name, "uplight");
  EXPECT_EQ(p.fixtures[2].modbus_base, 32);
  EXPECT_EQ(p.fixtures[2].pan_range_q16, 540 << 16);  // defaults
}

TEST(Patch, ResolveRejectsUnknownFixturesAndOverlaps) {
  Patch p;
  ASSERT_TRUE(ParsePatch(kFullPatch, "full.toml", &p).ok());
  Status st = ResolvePatch({{"spot"}}, &p);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("full.toml:"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("'wash'"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("it has: spot"), std::string::npos) << st.message();

  ASSERT_TRUE(ParsePatch("[[fixture]]\nname = \"a\"\nmodbus_base = 0\n[[fixture]]\nname = \"b\"\nmodbus_base = 4\n",
                         "o.toml", &p).ok());
  st = ResolvePatch({{"a"}, {"b"}}, &p);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("o.toml:4"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("overlap"), std::string::npos) << st.message();
}

TEST(Patch, ErrorsNameFileLineAndWhatWasExpected) {
  struct Case {
    const char* text;
    const char* line;
    const char* says;
  };
  const Case cases[] = {
      {"[[fixture]]\nname = \"a\"\nfade_ms = -1\n", "p.toml:3", "fade_ms"},
      {"[[fixture]]\nname = \"a\"\ndimmer_curve = \"log\"\n", "p.toml:3", "linear"},
      {"[[fixture]]\nname = \"a b\"\n", "p.toml:2", "A-Z"},
      {"[[fixture]]\nname = \"a\"\ncolour = 1\n", "p.toml:3", "unknown key 'colour'"},
      {"[[fixture]]\nname = \"a\"\n[[fixture]]\nname = \"a\"\n", "p.toml:3", "patched twice"},
      {"[modbus_tcp]\nlisten = \"localhost\"\n", "p.toml:2", "IPv4"},
      {"[modbus_tcp]\nport = 70000\n", "p.toml:2", "0..65535"},
      {"[modbus_rtu]\nbaud = 9600\n", "p.toml:1", "missing 'device'"},
      {"[modbus_rtu]\ndevice = \"/dev/x\"\nparity = \"mark\"\n", "p.toml:3", "parity"},
      {"[modbus_poller]\nmap = [ { register = 1, fixture = \"a\", param = \"iris\" } ]\n", "p.toml:2",
       "pan_fine, tilt"},
      {"[modbus_poller]\nmap = [ { register = 0, fixture = \"a\", param = \"r\" }, { register = 200, fixture = \"a\", "
       "param = \"g\" } ]\n",
       "p.toml:2", "125"},
      {"[[gpio_button]]\nchip = \"gpiochip0\"\nline = 3\naction = \"preset\"\npreset = [\"a.iris=1\"]\n", "p.toml:5",
       "unknown parameter"},
      {"[[gpio_encoder]]\nchip = \"c\"\nline_a = 1\nline_b = 1\nfixture = \"a\"\n", "p.toml:4", "differ"},
      {"[[gpio_encoder]]\nchip = \"c\"\nline_a = 1\nline_b = 2\nfixture = \"a\"\nparam = \"iris\"\n", "p.toml:6",
       "pan, tilt, roll, zoom, dimmer"},
      {"[[gpio_encoder]]\nchip = \"c\"\nline_a = 1\nline_b = 2\nfixture = \"a\"\nparam = \"roll\"\nstart = 800\n",
       "p.toml:7", "'start' must be in -720..720 degrees, got 800"},
      {"[[gpio_button]]\nchip = \"c\"\nline = 3\naction = \"preset\"\npreset = [\"a.roll=1000\"]\n", "p.toml:5",
       "roll must be in -720..720 degrees"},
      // Ranges and register layouts.
      {"[[fixture]]\nname = \"a\"\nroll_range_deg = 2000\n", "p.toml:3",
       "'roll_range_deg' must be in 1..1440 degrees, got 2000"},
      {"[[fixture]]\nname = \"a\"\npan_range_deg = 0\n", "p.toml:3", "'pan_range_deg' must be in 1..1440 degrees"},
      {"[[fixture]]\nname = \"a\"\nregisters = [\"dimmer\", \"pan_fine\"]\n", "p.toml:3",
       "registers: 'pan_fine' (+1) needs 'pan', its coarse byte"},
      {"[[fixture]]\nname = \"a\"\nregisters = [\"tilt\", \"roll_fine\", \"pan\"]\n", "p.toml:3",
       "'roll_fine' (+1) needs 'roll'"},
      {"[[fixture]]\nname = \"a\"\nregisters = [\"pan\", \"tilt\", \"pan\"]\n", "p.toml:3",
       "'pan' is listed twice (+0 and +2)"},
      {"[[fixture]]\nname = \"a\"\nregisters = [\n  \"dimmer\",\n  \"iris\",\n]\n", "p.toml:5",
       "unknown channel 'iris' (known: dimmer, pan, pan_fine"},
      // Zoom: an encoder starts from a beam angle the patch gives, in (0, 180).
      {"[[gpio_encoder]]\nchip = \"c\"\nline_a = 1\nline_b = 2\nfixture = \"a\"\nparam = \"zoom\"\n", "p.toml:1",
       "a zoom encoder needs 'start', the beam angle in degrees"},
      {"[[gpio_encoder]]\nchip = \"c\"\nline_a = 1\nline_b = 2\nfixture = \"a\"\nparam = \"zoom\"\nstart = 0\n",
       "p.toml:7", "'start' must be in 0.01..179.99 degrees, got 0"},
      {"[[fixture]]\nname = \"a\"\nregisters = [\"pan\", \"flags\"]\n", "p.toml:3", "needs 'dimmer'"},
      {"[[fixture]]\nname = \"a\"\nregisters = []\n", "p.toml:3", "at least one channel"},
      {"[[fixture]]\nname = \"a\"\nregisters = [1]\n", "p.toml:3", "channel names as strings"},
      {"[[fixture]]\nname = \"a\"\nregisters = \"pan\"\n", "p.toml:3", "must be an array"},
      {"[[fixture]]\nname = \"a\"\nmodbus_base = 65530\n", "p.toml:3",
       "modbus_base 65530 with 8 registers passes 65535"},
      {"[modbus_poller]\nmap = [ { register = 1, fixture = \"a\", param = \"flags\" } ]\n", "p.toml:2", "roll_fine"},
      {"[modbus_tcp\n", "p.toml:1", ""},
      {"fixture = 3\n", "p.toml:1", "array of tables"},
  };
  for (const Case& c : cases) {
    Patch p;
    const Status st = ParsePatch(c.text, "p.toml", &p);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << c.text;
    EXPECT_NE(st.message().find(c.line), std::string::npos) << c.text << " -> " << st.message();
    EXPECT_NE(st.message().find(c.says), std::string::npos) << c.text << " -> " << st.message();
  }
}

TEST(Patch, RegistersListRollAndFineBytesWithTheirRanges) {
  Patch p;
  Status st = ParsePatch(R"([[fixture]]
name = "spot"
modbus_base = 0
registers = ["dimmer", "pan", "pan_fine", "tilt", "tilt_fine", "roll", "roll_fine", "flags"]
roll_range_deg = 270
pan_range_deg = 360

[[fixture]]
name = "wash"

[modbus_poller]
map = [ { register = 4, fixture = "spot", param = "pan_fine" },
        { register = 5, fixture = "spot", param = "roll" } ]
)",
                         "l.toml", &p);
  ASSERT_TRUE(st.ok()) << st.ToString();
  const RegisterLayout& spot = p.fixtures[0].layout;
  ASSERT_EQ(spot.size(), 8);
  EXPECT_EQ(spot.OffsetOf(Channel::kPanFine), 2);
  EXPECT_EQ(spot.OffsetOf(Channel::kRollFine), 6);
  EXPECT_FALSE(spot.Has(Channel::kRed));
  EXPECT_EQ(p.fixtures[0].roll_range_q16, 270 << 16);
  EXPECT_EQ(p.fixtures[1].roll_range_q16, 360 << 16);  // default: a full turn
  EXPECT_TRUE(p.fixtures[1].layout == RegisterLayout());
  EXPECT_EQ(p.modbus_poller.map[0].channel, Channel::kPanFine);
  // Pan and tilt ranges the patch leaves out are the luminaire's (as the
  // engine's SetPanTilt16 reads them from the bake); given ones stay.
  ASSERT_TRUE(ResolvePatch({{"spot", 630 << 16, 265 << 16}, {"wash", 500 << 16, 200 << 16}, {"uplight"}}, &p).ok());
  EXPECT_EQ(p.fixtures[0].pan_range_q16, 360 << 16);
  EXPECT_EQ(p.fixtures[0].tilt_range_q16, 265 << 16);
  EXPECT_EQ(p.fixtures[1].pan_range_q16, 500 << 16);
  EXPECT_EQ(p.fixtures[1].tilt_range_q16, 200 << 16);
  EXPECT_EQ(p.fixtures[1].modbus_base, 8);  // after the spot's 8 registers
  EXPECT_EQ(p.fixtures[2].modbus_base, 16);

  // A poller entry for a register the fixture's layout does not have.
  ASSERT_TRUE(ParsePatch("[modbus_poller]\nmap = [\n  { register = 4, fixture = \"a\", param = \"roll\" },\n]\n",
                         "r.toml", &p).ok());
  st = ResolvePatch({{"a"}}, &p);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("r.toml:3: [modbus_poller] map: fixture 'a' has no 'roll' register"), std::string::npos)
      << st.message();
}

TEST(Patch, ZoomIsARegisterAndAnEncoderParameter) {
  Patch p;
  const Status st = ParsePatch(R"([[fixture]]
name = "spot"
registers = ["dimmer", "pan", "tilt", "zoom"]

[modbus_poller]
map = [ { register = 7, fixture = "spot", param = "zoom" } ]

[[gpio_encoder]]
chip = "gpiochip0"
line_a = 1
line_b = 2
fixture = "spot"
param = "zoom"
step = 0.5
start = 24
)",
                               "z.toml", &p);
  ASSERT_TRUE(st.ok()) << st.ToString();
  EXPECT_EQ(p.fixtures[0].layout.OffsetOf(Channel::kZoom), 3);
  EXPECT_EQ(p.modbus_poller.map[0].channel, Channel::kZoom);
  ASSERT_EQ(p.encoders.size(), 1u);
  EXPECT_EQ(p.encoders[0].param, Param::kZoom);
  EXPECT_EQ(p.encoders[0].step, 1 << 15);  // 0.5 degrees, Q16.16
  EXPECT_EQ(p.encoders[0].start, 24 << 16);
  EXPECT_TRUE(ResolvePatch({{"spot"}}, &p).ok());
}

TEST(Patch, BlocksOfEveryLayoutMustNotOverlap) {
  Patch p;
  ASSERT_TRUE(ParsePatch(R"([[fixture]]
name = "a"
modbus_base = 0
registers = ["dimmer", "pan", "pan_fine", "tilt", "tilt_fine", "roll", "r", "g", "b", "flags"]

[[fixture]]
name = "b"
modbus_base = 8
)",
                         "o.toml", &p).ok());
  const Status st = ResolvePatch({{"a"}, {"b"}}, &p);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("o.toml:6: fixture 'b': registers 8..15 overlap fixture 'a' at 0..9"), std::string::npos)
      << st.message();
}

TEST(Patch, MissingFileIsNotFound) {
  Patch p;
  const Status st = LoadPatch("/nonexistent/patch.toml", &p);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("/nonexistent/patch.toml"), std::string::npos);
}

}  // namespace
}  // namespace relight::hal
