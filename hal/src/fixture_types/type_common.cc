#include "fixture_types/type_common.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "relight/hal/dmx/fixture_type.h"

namespace relight::hal {

Status ReadTypeFile(const std::string& path, std::string* text) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) {
    return Status(errno == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError,
                  path + ": " + std::strerror(errno));
  }
  if (!S_ISREG(st.st_mode)) return Status(StatusCode::kIoError, path + ": not a regular file");
  if (st.st_size > (4 << 20)) return Status(StatusCode::kInvalidArgument, path + ": larger than 4 MiB");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  *text = ss.str();
  return Status::Ok();
}

const char* DmxFunctionName(DmxFunction f) {
  switch (f) {
    case DmxFunction::kIgnored: return "ignored";
    case DmxFunction::kDimmer: return "dimmer";
    case DmxFunction::kDimmerFine: return "dimmer_fine";
    case DmxFunction::kPan: return "pan";
    case DmxFunction::kPanFine: return "pan_fine";
    case DmxFunction::kTilt: return "tilt";
    case DmxFunction::kTiltFine: return "tilt_fine";
    case DmxFunction::kRed: return "red";
    case DmxFunction::kGreen: return "green";
    case DmxFunction::kBlue: return "blue";
    case DmxFunction::kWhite: return "white";
    case DmxFunction::kCyan: return "cyan";
    case DmxFunction::kMagenta: return "magenta";
    case DmxFunction::kYellow: return "yellow";
    case DmxFunction::kColorWheel: return "color_wheel";
    case DmxFunction::kZoom: return "zoom";
    case DmxFunction::kShutter: return "shutter";
    case DmxFunction::kX: return "x";
    case DmxFunction::kY: return "y";
    case DmxFunction::kSize: return "size";
    case DmxFunction::kCount: break;
  }
  return "?";
}

const DmxMode* FixtureType::FindMode(const std::string& name) const {
  for (const DmxMode& m : modes) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

Status LoadFixtureType(const std::string& path, FixtureType* out) {
  auto ends_with = [&](const char* ext) {
    const size_t n = std::strlen(ext);
    return path.size() >= n && path.compare(path.size() - n, n, ext) == 0;
  };
  if (ends_with(".qxf")) return LoadQxf(path, out);
  if (ends_with(".toml")) return LoadFixtureTypeToml(path, out);
  return Status(StatusCode::kUnsupported, path + ": a fixture type is a .qxf (QLC+) or .toml file");
}

}  // namespace relight::hal
