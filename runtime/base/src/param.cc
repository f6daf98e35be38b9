#include "relight/base/param.h"

namespace relight {

const char* ParamName(Param param) {
  switch (param) {
    case Param::kPan: return "pan";
    case Param::kTilt: return "tilt";
    case Param::kDimmer: return "dimmer";
    case Param::kRed: return "r";
    case Param::kGreen: return "g";
    case Param::kBlue: return "b";
    case Param::kRoll: return "roll";
    case Param::kZoom: return "zoom";
    case Param::kX: return "x";
    case Param::kY: return "y";
    case Param::kSize: return "size";
  }
  return "?";
}

bool ParamFromName(const std::string& name, Param* out) {
  for (int p = 0; p < kParamCount; ++p) {
    if (name == ParamName(static_cast<Param>(p))) {
      *out = static_cast<Param>(p);
      return true;
    }
  }
  return false;
}

}  // namespace relight
