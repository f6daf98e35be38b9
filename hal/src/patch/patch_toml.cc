// Patch file reader: TOML -> Patch, every error as "file:line: what".
#include <arpa/inet.h>
#include <toml++/toml.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include "../bounded_file.h"
#include "toml_table.h"
#include "relight/hal/param_text.h"
#include "relight/hal/patch.h"

namespace relight::hal {
using namespace patch_reader;  // NOLINT: this file is the reader
namespace {

int32_t DegreesQ16(double deg) { return static_cast<int32_t>(std::llround(deg * 65536.0)); }
int32_t LevelQ15(double level) { return static_cast<int32_t>(std::lround(level * 32767.0)); }

Param ParseParamName(const Table& t, const char* key, const std::string& name) {
  Param param = Param::kDimmer;
  if (!ParamFromName(name, &param)) {
    t.Fail(t.Node(key),
           std::string("'") + key + "' must be one of pan, tilt, roll, zoom, dimmer, r, g, b; got '" + name + "'");
  }
  return param;
}

// A poller entry drives one of the fixture's parameter registers.
Channel ParseChannelName(const Table& t, const char* key, const std::string& name) {
  Channel channel = Channel::kDimmer;
  if (!ChannelFromName(name, &channel) || channel == Channel::kProfile || channel == Channel::kFlags) {
    t.Fail(t.Node(key), std::string("'") + key +
                            "' must be one of dimmer, pan, pan_fine, tilt, tilt_fine, roll, roll_fine, r, g, b, zoom, x, y, size; "
                            "got '" +
                            name + "'");
  }
  return channel;
}

// `registers = ["dimmer", "pan", "pan_fine", ...]`: the fixture's layout
// (register_layout.h); the standard 8 when absent.
RegisterLayout ParseLayout(const Table& t) {
  const toml::array* list = t.Array("registers");
  if (list == nullptr) return RegisterLayout();
  std::vector<Channel> channels;
  for (const toml::node& item : *list) {
    const auto name = item.value<std::string>();
    if (!item.is_string() || !name) {
      t.Fail(&item, "registers must list channel names as strings, e.g. [\"dimmer\", \"pan\", \"pan_fine\"]");
    }
    Channel channel = Channel::kDimmer;
    if (!ChannelFromName(*name, &channel)) {
      t.Fail(&item, "registers: unknown channel '" + *name + "' (known: " + ChannelNames() + ")");
    }
    channels.push_back(channel);
  }
  RegisterLayout layout;
  std::string error;
  if (!RegisterLayout::FromChannels(channels, &layout, &error)) t.Fail(t.Node("registers"), "registers: " + error);
  return layout;
}

}  // namespace

namespace patch_reader {

void ParseName(const Table& t, std::string* name) {
  *name = t.String("name", "", true);
  NamedChange probe[3];
  std::string error;
  if (ParseParamText(*name + ".dimmer=0", 0, probe, &error) != 1) {
    t.Fail(t.Node("name"), "name '" + *name + "' must be 1.." + std::to_string(kMaxFixtureName) +
                               " of A-Z a-z 0-9 _ -");
  }
}

void ParseControls(const Table& t, const RegisterLayout& default_layout, FixturePatch* f) {
  f->layout = t.Has("registers") ? ParseLayout(t) : default_layout;
  f->modbus_base = static_cast<int>(t.Int("modbus_base", -1, 0, 65535));
  if (f->modbus_base + f->layout.size() > 65536) {
    t.Fail(t.Node("modbus_base"), "modbus_base " + std::to_string(f->modbus_base) + " with " +
                                      std::to_string(f->layout.size()) + " registers passes 65535");
  }
  const std::string curve = t.String("dimmer_curve", "linear");
  if (curve == "linear") {
    f->dimmer_curve = DimmerCurve::kLinear;
  } else if (curve == "square") {
    f->dimmer_curve = DimmerCurve::kSquare;
  } else {
    t.Fail(t.Node("dimmer_curve"), "dimmer_curve must be \"linear\" or \"square\", got \"" + curve + "\"");
  }
  f->fade_ms = static_cast<int32_t>(t.Int("fade_ms", 0, 0, 600000));
}

}  // namespace patch_reader

namespace {

void ParseFixture(const Table& t, Patch* patch) {
  t.CheckKeys({"name", "modbus_base", "registers", "pan_range_deg", "tilt_range_deg", "roll_range_deg", "dimmer_curve",
               "fade_ms"});
  FixturePatch f;
  f.line = t.line();
  ParseName(t, &f.name);
  ParseControls(t, RegisterLayout(), &f);
  // Absent pan and tilt ranges stay 0: ResolvePatch takes the luminaire's.
  f.pan_range_q16 = DegreesQ16(t.Number("pan_range_deg", 0, 1, 1440, " degrees"));
  f.tilt_range_q16 = DegreesQ16(t.Number("tilt_range_deg", 0, 1, 1440, " degrees"));
  f.roll_range_q16 = DegreesQ16(t.Number("roll_range_deg", 360, 1, 1440, " degrees"));
  for (const FixturePatch& other : patch->fixtures) {
    if (other.name == f.name) {
      t.Fail(nullptr, "fixture '" + f.name + "' is patched twice (first at line " + std::to_string(other.line) + ")");
    }
  }
  patch->fixtures.push_back(f);
}

void ParseTcp(const Table& t, Patch* patch) {
  t.CheckKeys({"listen", "port", "allow", "max_clients", "idle_timeout_ms", "request_timeout_ms"});
  ModbusTcpConfig& c = patch->modbus_tcp;
  c.enabled = true;
  c.listen = t.String("listen", c.listen);
  in_addr addr{};
  if (inet_pton(AF_INET, c.listen.c_str(), &addr) != 1) {
    t.Fail(t.Node("listen"), "listen must be an IPv4 address such as \"127.0.0.1\", got \"" + c.listen + "\"");
  }
  c.port = static_cast<int>(t.Int("port", c.port, 0, 65535));
  if (const toml::array* allow = t.Array("allow")) {
    for (const toml::node& item : *allow) {
      const auto v = item.value<std::string>();
      if (!item.is_string() || inet_pton(AF_INET, v->c_str(), &addr) != 1) {
        t.Fail(&item, "allow must list IPv4 addresses as strings, e.g. [\"127.0.0.1\"]");
      }
      c.allow.push_back(*v);
    }
  }
  c.max_clients = static_cast<int>(t.Int("max_clients", c.max_clients, 1, 256));
  c.idle_timeout_ms = static_cast<int>(t.Int("idle_timeout_ms", c.idle_timeout_ms, 100, 86400000));
  c.request_timeout_ms = static_cast<int>(t.Int("request_timeout_ms", c.request_timeout_ms, 100, 600000));
}

void ParseRtu(const Table& t, Patch* patch) {
  t.CheckKeys({"device", "baud", "parity", "data_bits", "stop_bits", "unit_id"});
  ModbusRtuConfig& c = patch->modbus_rtu;
  c.enabled = true;
  c.device = t.String("device", "", true);
  c.baud = static_cast<int>(t.Int("baud", c.baud, 300, 4000000));
  const std::string parity = t.String("parity", "none");
  if (parity == "none") {
    c.parity = 'N';
  } else if (parity == "even") {
    c.parity = 'E';
  } else if (parity == "odd") {
    c.parity = 'O';
  } else {
    t.Fail(t.Node("parity"), "parity must be \"none\", \"even\" or \"odd\", got \"" + parity + "\"");
  }
  c.data_bits = static_cast<int>(t.Int("data_bits", c.data_bits, 7, 8));
  c.stop_bits = static_cast<int>(t.Int("stop_bits", c.stop_bits, 1, 2));
  c.unit_id = static_cast<int>(t.Int("unit_id", c.unit_id, 1, 247));
}

void ParsePoller(const Table& t, const std::string& where, Patch* patch) {
  t.CheckKeys({"host", "port", "unit_id", "rate_hz", "timeout_ms", "backoff_max_ms", "map"});
  ModbusPollerConfig& c = patch->modbus_poller;
  c.enabled = true;
  c.host = t.String("host", c.host);
  in_addr addr{};
  if (inet_pton(AF_INET, c.host.c_str(), &addr) != 1) {
    t.Fail(t.Node("host"), "host must be an IPv4 address, got \"" + c.host + "\"");
  }
  c.port = static_cast<int>(t.Int("port", c.port, 1, 65535));
  c.unit_id = static_cast<int>(t.Int("unit_id", c.unit_id, 0, 255));
  c.rate_hz = static_cast<int>(t.Int("rate_hz", c.rate_hz, 1, 1000));
  c.timeout_ms = static_cast<int>(t.Int("timeout_ms", c.timeout_ms, 10, 60000));
  c.backoff_max_ms = static_cast<int>(t.Int("backoff_max_ms", c.backoff_max_ms, 10, 600000));
  const toml::array* map = t.Array("map");
  if (map == nullptr || map->empty()) t.Fail(nullptr, "needs a 'map' of {register, fixture, param} entries");
  for (const toml::node& item : *map) {
    if (!item.is_table()) t.Fail(&item, "each map entry must be {register = N, fixture = \"name\", param = \"dimmer\"}");
    const Table e(*item.as_table(), where, "[modbus_poller] map entry");
    e.CheckKeys({"register", "fixture", "param"});
    PollEntry entry;
    entry.line = static_cast<int>(item.source().begin.line);
    entry.peer_register = static_cast<int>(e.Int("register", 0, 0, 65535, true));
    entry.fixture = e.String("fixture", "", true);
    entry.channel = ParseChannelName(e, "param", e.String("param", "", true));
    c.map.push_back(entry);
  }
  int lo = 65535, hi = 0;
  for (const PollEntry& e : c.map) {
    lo = e.peer_register < lo ? e.peer_register : lo;
    hi = e.peer_register > hi ? e.peer_register : hi;
  }
  if (hi - lo + 1 > 125) {
    t.Fail(t.Node("map"), "mapped registers span " + std::to_string(hi - lo + 1) +
                              " addresses; one read covers at most 125");
  }
}

void ParseButton(const Table& t, Patch* patch) {
  t.CheckKeys({"chip", "line", "active_low", "debounce_ms", "action", "fixture", "on_level", "preset"});
  GpioButtonConfig b;
  b.config_line = t.line();
  b.chip = t.String("chip", "", true);
  b.line = static_cast<int>(t.Int("line", 0, 0, 1023, true));
  b.active_low = t.Bool("active_low", true);
  b.debounce_ms = static_cast<int>(t.Int("debounce_ms", b.debounce_ms, 0, 1000));
  const std::string action = t.String("action", "toggle");
  if (action == "toggle") {
    b.action = ButtonAction::kToggle;
    b.fixture = t.String("fixture", "", true);
    b.on_level_q15 = LevelQ15(t.Number("on_level", 1.0, 0.0, 1.0));
    if (t.Has("preset")) t.Fail(t.Node("preset"), "'preset' goes with action = \"preset\"");
  } else if (action == "preset") {
    b.action = ButtonAction::kPreset;
    const toml::array* preset = t.Array("preset");
    if (preset == nullptr || preset->empty()) {
      t.Fail(nullptr, "action = \"preset\" needs preset = [\"FIXTURE.PARAM=VALUE\", ...]");
    }
    for (const toml::node& item : *preset) {
      const auto text = item.value<std::string>();
      NamedChange parsed[3];
      std::string error;
      const int n = item.is_string() ? ParseParamText(*text, 0, parsed, &error) : 0;
      if (n == 0) t.Fail(&item, "preset: " + (item.is_string() ? error : std::string("entries must be strings")));
      b.preset.insert(b.preset.end(), parsed, parsed + n);
    }
  } else {
    t.Fail(t.Node("action"), "action must be \"toggle\" or \"preset\", got \"" + action + "\"");
  }
  patch->buttons.push_back(std::move(b));
}

void ParseEncoder(const Table& t, Patch* patch) {
  t.CheckKeys({"chip", "line_a", "line_b", "fixture", "param", "step", "start"});
  GpioEncoderConfig e;
  e.config_line = t.line();
  e.chip = t.String("chip", "", true);
  e.line_a = static_cast<int>(t.Int("line_a", 0, 0, 1023, true));
  e.line_b = static_cast<int>(t.Int("line_b", 0, 0, 1023, true));
  if (e.line_a == e.line_b) t.Fail(t.Node("line_b"), "line_a and line_b must differ");
  e.fixture = t.String("fixture", "", true);
  e.param = ParseParamName(t, "param", t.String("param", "dimmer"));
  if (e.param == Param::kZoom) {
    // A beam angle has no natural 0 to step from: the encoder starts where the patch says.
    if (t.Node("start") == nullptr) {
      t.Fail(nullptr, "a zoom encoder needs 'start', the beam angle in degrees it starts from (e.g. the luminaire's "
                      "default zoom)");
    }
    e.step = DegreesQ16(t.Number("step", 1.0, 0.001, 90.0, " degrees"));
    e.start = DegreesQ16(t.Number("start", 0.0, 0.01, 179.99, " degrees"));
  } else if (IsAngle(e.param)) {
    e.step = DegreesQ16(t.Number("step", 1.0, 0.001, 90.0, " degrees"));
    e.start = DegreesQ16(t.Number("start", 0.0, -720.0, 720.0, " degrees"));
  } else {
    e.step = LevelQ15(t.Number("step", 0.01, 1.0 / 32767.0, 1.0));
    e.start = LevelQ15(t.Number("start", 0.0, 0.0, 1.0));
  }
  patch->encoders.push_back(e);
}

}  // namespace

Status ParsePatch(const std::string& text, const std::string& where, Patch* out) {
  Patch patch;
  patch.where = where;
  try {
    toml::table root;
    try {
      root = toml::parse(text, where);
    } catch (const toml::parse_error& e) {
      return Status(StatusCode::kInvalidArgument, where + ":" + std::to_string(e.source().begin.line) + ": " +
                                                      std::string(e.description()));
    }
    const Table top(root, where, "patch");
    top.CheckKeys({"fixture", "emitter", "modbus_tcp", "modbus_rtu", "modbus_poller", "gpio_button", "gpio_encoder",
                   "replay"});
    ForEachTable(root, where, "fixture", [&](const toml::table& t, int i) {
      ParseFixture(Table(t, where, "fixture " + std::to_string(i)), &patch);
    });
    ForEachTable(root, where, "emitter", [&](const toml::table& t, int i) {
      ParseEmitter(Table(t, where, "emitter " + std::to_string(i)), &patch);
    });
    if (const toml::table* t = Section(root, where, "modbus_tcp")) ParseTcp(Table(*t, where, "[modbus_tcp]"), &patch);
    if (const toml::table* t = Section(root, where, "modbus_rtu")) ParseRtu(Table(*t, where, "[modbus_rtu]"), &patch);
    if (const toml::table* t = Section(root, where, "modbus_poller")) {
      ParsePoller(Table(*t, where, "[modbus_poller]"), where, &patch);
    }
    ForEachTable(root, where, "gpio_button", [&](const toml::table& t, int i) {
      ParseButton(Table(t, where, "gpio_button " + std::to_string(i)), &patch);
    });
    ForEachTable(root, where, "gpio_encoder", [&](const toml::table& t, int i) {
      ParseEncoder(Table(t, where, "gpio_encoder " + std::to_string(i)), &patch);
    });
    if (const toml::table* t = Section(root, where, "replay")) {
      const Table replay(*t, where, "[replay]");
      replay.CheckKeys({"script"});
      patch.replay_script = replay.String("script", "", true);
    }
  } catch (const PatchError& e) {
    return Status(StatusCode::kInvalidArgument, e.message);
  }
  *out = std::move(patch);
  return Status::Ok();
}

Status LoadPatch(const std::string& path, Patch* out) {
  std::string text;
  RELIGHT_RETURN_IF_ERROR(ReadConfigFile(path, "patch", &text));  // bounded: not /dev/zero or a FIFO
  return ParsePatch(text, path, out);
}

}  // namespace relight::hal
