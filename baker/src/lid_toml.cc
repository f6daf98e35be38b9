// Reads and validates a luminaire's luminous intensity distribution.
#include "lid_toml.h"

#include <algorithm>
#include <string>

#include "relight/baker/photometric_file.h"

namespace relight::baker {

namespace {

// Control points: gamma from 0, strictly increasing, up to 180 degrees;
// candela >= 0 and not all zero. Past the last point the intensity is 0.
void ReadTable(const TomlFields& f, Lid* lid) {
  const toml::array& gamma = f.Array("gamma");
  const toml::array& candela = f.Array("candela");
  if (gamma.size() < 2) {
    f.Fail(f.Required("gamma"),
           "gamma needs at least 2 angles (0 first), got " + Describe(f.Required("gamma")));
  }
  if (candela.size() != gamma.size()) {
    f.Fail(f.Required("candela"), "candela must have one value per gamma angle (" +
                                      std::to_string(gamma.size()) + "), got " +
                                      Describe(f.Required("candela")));
  }
  for (size_t i = 0; i < gamma.size(); ++i) {
    const toml::node& node = *gamma.get(i);
    const double g = f.ReadNumber(node, "gamma", Closed(0, 180));
    if (i == 0 && g != 0.0) f.Fail(node, "gamma must start at 0, got " + Describe(node));
    if (i > 0 && !(g > lid->gamma_deg.back())) {
      f.Fail(node, "gamma must be strictly increasing, got " + Describe(node) + " after " +
                       FormatNumber(lid->gamma_deg.back()));
    }
    lid->gamma_deg.push_back(g);
    lid->candela.push_back(f.ReadNumber(*candela.get(i), "candela", NonNegative()));
  }
  lid->peak_cd = *std::max_element(lid->candela.begin(), lid->candela.end());
  if (!(lid->peak_cd > 0.0)) f.Fail(f.Required("candela"), "candela must not all be 0");
}

// A photometric file (.ies / .ldt), relative to the scene file's folder.
// One C plane: an axisymmetric table; otherwise the full (C, gamma) table.
void ReadFile(const TomlFields& f, Lid* lid) {
  const std::string rel = f.String("path");
  const size_t slash = f.file().find_last_of('/');
  const std::string folder = slash == std::string::npos ? "" : f.file().substr(0, slash + 1);
  const std::string path = !rel.empty() && rel[0] == '/' ? rel : folder + rel;
  try {
    *lid = LoadLid(path);
  } catch (const SceneError& e) {
    f.Fail(f.Required("path"), std::string("cannot use the photometric file: ") + e.what());
  }
}

}  // namespace

Lid ReadLid(const TomlFields& f) {
  Lid lid;
  const std::string type = f.String("type");
  if (type == "isotropic") {
    f.CheckKeys({"type", "peak_cd"});
    lid.kind = LidKind::kIsotropic;
    lid.peak_cd = f.Number("peak_cd", Positive());
  } else if (type == "cos") {
    f.CheckKeys({"type", "exponent", "spread", "peak_cd"});
    lid.kind = LidKind::kCosPower;
    lid.exponent = f.Number("exponent", Closed(0, 10000));
    lid.spread_deg = f.Number("spread", OpenClosed(0, 180));
    lid.peak_cd = f.Number("peak_cd", Positive());
  } else if (type == "table") {
    f.CheckKeys({"type", "gamma", "candela"});
    lid.kind = LidKind::kTable;
    ReadTable(f, &lid);
  } else if (type == "file") {
    f.CheckKeys({"type", "path"});
    ReadFile(f, &lid);
  } else {
    f.Fail(f.Required("type"), "type must be \"isotropic\", \"cos\", \"table\" or \"file\", got " +
                                   Describe(f.Required("type")));
  }
  return lid;
}

}  // namespace relight::baker
