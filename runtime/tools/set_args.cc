#include "set_args.h"

#include "relight/control/engine_binding.h"

namespace relight::cli {

bool ParseSetArg(const std::string& text, SetArg* out, std::string* error) {
  hal::NamedChange changes[3];
  const int n = hal::ParseParamText(text, 0, changes, error);
  if (n == 0) {
    *error = "--set " + *error;
    return false;
  }
  SetArg arg;
  arg.fixture = changes[0].fixture;
  if (n == 3) {
    arg.param = "colour";
  } else {
    arg.param = ParamName(changes[0].change.param);
  }
  for (int i = 0; i < n; ++i) {
    const ParamChange& c = changes[i].change;
    arg.values.push_back(IsAngle(c.param) ? c.degrees.raw() / 65536.0 : c.level.raw() / 32767.0);
  }
  *out = std::move(arg);
  return true;
}

bool ApplyChange(Engine& engine, const ParamChange& change, std::string* error) {
  if (const Status st = control::ApplyToEngine(engine, change); !st.ok()) {
    const std::string name =
        change.fixture < engine.luminaire_count() ? engine.bake().luminaires[change.fixture].name : "?";
    *error = name + "." + ParamName(change.param) + ": " + st.ToString();
    return false;
  }
  return true;
}

bool ApplySetText(Engine& engine, const std::string& text, std::string* error) {
  hal::NamedChange changes[3];
  const int n = hal::ParseParamText(text, 0, changes, error);
  if (n == 0) {
    *error = "--set " + *error;
    return false;
  }
  std::vector<uint16_t> index;
  if (const Status st = control::BindNames(engine, {changes[0].fixture}, "--set '" + text + "'", &index); !st.ok()) {
    *error = st.message();
    return false;
  }
  for (int i = 0; i < n; ++i) {
    ParamChange c = changes[i].change;
    c.fixture = index[0];
    if (!ApplyChange(engine, c, error)) {
      *error = "--set '" + text + "': " + *error;
      return false;
    }
  }
  return true;
}

}  // namespace relight::cli
