// The real libgpiod backend's start-up errors. No GPIO chip exists on these
// machines (and gpio-sim cannot be loaded), so behaviour is tested through
// the mock, which shares the decoder; here: a missing chip and a device that
// is not a GPIO chip are clear errors naming the chip and the patch entry.
#include <gtest/gtest.h>

#include "relight/hal/gpiod_source.h"

namespace relight::hal {
namespace {

Patch ButtonOn(const std::string& chip) {
  Patch p;
  p.where = "panel.toml";
  GpioButtonConfig b;
  b.chip = chip;
  b.line = 4;
  b.fixture = "spot";
  p.buttons.push_back(b);
  return p;
}

TEST(GpiodSource, MissingChipIsAStartUpErrorNamingIt) {
  GpiodSource source(ButtonOn("gpiochip_relight_test_absent"));
  const Status st = source.Start();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("gpiochip_relight_test_absent"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("panel.toml"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("gpio_button 1"), std::string::npos) << st.message();
}

TEST(GpiodSource, ADeviceThatIsNotAGpioChipIsRefused) {
  GpiodSource source(ButtonOn("/dev/null"));
  const Status st = source.Start();
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("/dev/null"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("not a GPIO chip"), std::string::npos) << st.message();
  // Nothing was opened: polling is harmless and yields nothing.
  ParamChange out[4];
  EXPECT_EQ(source.Poll(0, out, 4), 0u);
}

TEST(GpiodSource, EncoderLinesAreCheckedToo) {
  Patch p;
  GpioEncoderConfig e;
  e.chip = "/nonexistent/gpiochip7";
  e.line_a = 1;
  e.line_b = 2;
  e.fixture = "spot";
  p.encoders.push_back(e);
  GpiodSource source(p);
  const Status st = source.Start();
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("gpio_encoder 1 A"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace relight::hal
