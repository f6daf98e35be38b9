// DMX patch file (TOML) -> DmxPatch, every error as "file:line: what".
#include <sys/stat.h>
#include <toml++/toml.h>

#include <fstream>
#include <sstream>

#include "../bounded_file.h"
#include "relight/hal/dmx/dmx_patch.h"

namespace relight::hal {
namespace {

struct DmxPatchError {
  std::string message;
};

std::string Dir(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

bool IsFile(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

class Reader {
 public:
  Reader(const std::string& where, const std::string& library_dir) : where_(where), library_dir_(library_dir) {}

  [[noreturn]] void Fail(const toml::node& node, const std::string& why) const {
    Fail(static_cast<int>(node.source().begin.line), why);
  }
  [[noreturn]] void Fail(int line, const std::string& why) const {
    throw DmxPatchError{where_ + ":" + std::to_string(line) + ": " + why};
  }

  void CheckKeys(const toml::table& t, std::initializer_list<const char*> allowed, const char* what) const {
    for (const auto& [key, node] : t) {
      bool known = false;
      for (const char* a : allowed) known = known || key.str() == a;
      if (!known) Fail(node, std::string(what) + ": unknown key '" + std::string(key.str()) + "'");
    }
  }

  std::string Str(const toml::table& t, const char* key, const char* what) const {
    const toml::node* n = t.get(key);
    if (n == nullptr) Fail(t, std::string(what) + ": missing '" + key + "'");
    if (!n->is_string()) Fail(*n, std::string(what) + ": '" + key + "' must be a string");
    return *n->value<std::string>();
  }

  int Int(const toml::table& t, const char* key, const char* what, int lo, int hi, int fallback, bool required) const {
    const toml::node* n = t.get(key);
    if (n == nullptr) {
      if (required) Fail(t, std::string(what) + ": missing '" + key + "'");
      return fallback;
    }
    if (!n->is_integer()) Fail(*n, std::string(what) + ": '" + key + "' must be an integer");
    const int64_t v = *n->value<int64_t>();
    if (v < lo || v > hi) {
      Fail(*n, std::string(what) + ": '" + key + "' must be in " + std::to_string(lo) + ".." + std::to_string(hi) +
                   ", got " + std::to_string(v));
    }
    return static_cast<int>(v);
  }

  void Settings(const toml::table& t, DmxPatch* out) const {
    CheckKeys(t, {"loss_of_signal", "loss_timeout_ms", "loss_fade_ms"}, "[dmx]");
    if (t.contains("loss_of_signal")) {
      const std::string p = Str(t, "loss_of_signal", "[dmx]");
      if (p == "hold") out->loss_policy = DmxLossPolicy::kHold;
      else if (p == "blackout") out->loss_policy = DmxLossPolicy::kBlackout;
      else if (p == "fade") out->loss_policy = DmxLossPolicy::kFade;
      else Fail(*t.get("loss_of_signal"), "[dmx]: loss_of_signal is \"hold\", \"fade\" or \"blackout\", got \"" + p + "\"");
    }
    out->loss_timeout_ms = Int(t, "loss_timeout_ms", "[dmx]", 50, 600000, out->loss_timeout_ms, false);
    out->loss_fade_ms = Int(t, "loss_fade_ms", "[dmx]", 1, 600000, out->loss_fade_ms, false);
    if (t.contains("loss_fade_ms") && out->loss_policy != DmxLossPolicy::kFade) {
      Fail(*t.get("loss_fade_ms"), "[dmx]: loss_fade_ms is for loss_of_signal = \"fade\"");
    }
  }

  void Fixture(const toml::table& t, DmxPatch* out) const {
    CheckKeys(t, {"name", "type", "mode", "universe", "address"}, "dmx_fixture");
    DmxFixturePatch f;
    f.line = static_cast<int>(t.source().begin.line);
    f.name = Str(t, "name", "dmx_fixture");
    const std::string what = "dmx_fixture '" + f.name + "'";
    for (const DmxFixturePatch& other : out->fixtures) {
      if (other.name == f.name) Fail(t, what + ": name already used at line " + std::to_string(other.line));
    }
    const std::string type = Str(t, "type", what.c_str());
    f.mode = Str(t, "mode", what.c_str());
    f.universe = Int(t, "universe", what.c_str(), 0, 0x7fffffff, 1, true);
    f.address = Int(t, "address", what.c_str(), 1, kDmxSlots, 1, true);

    const std::string local = type.empty() || type[0] == '/' ? type : Dir(where_) + "/" + type;
    const std::string library = library_dir_ + "/" + type;
    f.type_path = IsFile(local) ? local : library;
    if (!IsFile(f.type_path)) {
      Fail(*t.get("type"), what + ": unknown fixture type '" + type + "' (neither " + local + " nor " + library +
                               " exists)");
    }
    const Status loaded = LoadFixtureType(f.type_path, &f.type);
    if (!loaded.ok()) Fail(*t.get("type"), what + ": type: " + loaded.message());
    const Status built = BuildPersonality(f.type, f.mode, &f.personality);
    if (!built.ok()) Fail(*t.get("mode"), what + ": " + built.message());

    const int last = f.address + f.personality.footprint - 1;
    if (last > kDmxSlots) {
      Fail(*t.get("address"), what + ": mode '" + f.mode + "' takes " + std::to_string(f.personality.footprint) +
                                  " slots, so address " + std::to_string(f.address) + " ends at " +
                                  std::to_string(last) + ", past 512");
    }
    for (const DmxFixturePatch& o : out->fixtures) {
      const int o_last = o.address + o.personality.footprint - 1;
      if (o.universe == f.universe && f.address <= o_last && o.address <= last) {
        Fail(*t.get("address"), what + ": slots " + std::to_string(f.address) + ".." + std::to_string(last) +
                                    " of universe " + std::to_string(f.universe) + " overlap '" + o.name + "' (" +
                                    std::to_string(o.address) + ".." + std::to_string(o_last) + ", line " +
                                    std::to_string(o.line) + ")");
      }
    }
    out->fixtures.push_back(std::move(f));
  }

  void Patch(const toml::table& root, DmxPatch* out) const {
    CheckKeys(root, {"dmx", "dmx_fixture"}, "DMX patch");
    if (const toml::node* s = root.get("dmx")) {
      if (!s->is_table()) Fail(*s, "[dmx] must be a table");
      Settings(*s->as_table(), out);
    }
    const toml::node* list = root.get("dmx_fixture");
    if (list == nullptr) return;
    if (!list->is_array_of_tables()) Fail(*list, "dmx_fixture must be [[dmx_fixture]] tables");
    for (const toml::node& n : *list->as_array()) Fixture(*n.as_table(), out);
  }

 private:
  const std::string& where_;
  const std::string& library_dir_;
};

}  // namespace

Status ParseDmxPatch(const std::string& text, const std::string& where, DmxPatch* out,
                     const std::string& library_dir) {
  *out = DmxPatch{};
  out->where = where;
  try {
    const toml::table root = toml::parse(text, where);
    Reader(where, library_dir).Patch(root, out);
  } catch (const toml::parse_error& e) {
    return Status(StatusCode::kInvalidArgument,
                  where + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description()));
  } catch (const DmxPatchError& e) {
    return Status(StatusCode::kInvalidArgument, e.message);
  }
  return Status::Ok();
}

Status LoadDmxPatch(const std::string& path, DmxPatch* out, const std::string& library_dir) {
  std::string text;
  RELIGHT_RETURN_IF_ERROR(ReadConfigFile(path, "DMX patch", &text));  // bounded: not /dev/zero or a FIFO
  return ParseDmxPatch(text, path, out, library_dir);
}

}  // namespace relight::hal
