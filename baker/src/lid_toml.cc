// Reads and validates a luminaire's luminous intensity distribution.
#include "lid_toml.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "relight/baker/beam_profile.h"
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

// The bake's bounds (runtime/bake/include/relight/bake/bake_limits.h): lumens
// up to 2^32 lm, any intensity up to 2^31 cd.
constexpr double kMaxLumens = 4294967296.0;
constexpr double kMaxPeakCd = 2147483648.0;
constexpr double kMaxFieldOverBeam = 4.0;

// A zoom optic's beam model (beam_profile.h): the beam angle, the field
// angle (or the Gaussian default), lumens or the peak at the beam angle, and
// an optional zoom range the beam angle moves in at run time.
void ReadBeam(const TomlFields& f, Lid* lid) {
  lid->kind = LidKind::kBeam;
  const Range angle{0, 180, true, true};
  lid->beam_deg = f.Number("beam_angle", angle);
  double ratio = DefaultFieldOverBeam();
  if (f.Has("field_angle")) {
    const double field = f.Number("field_angle", Positive());
    if (!(field > lid->beam_deg && field <= kMaxFieldOverBeam * lid->beam_deg)) {
      f.Fail(f.Required("field_angle"),
             "field_angle (full angle at 10 % of peak) must be in (beam_angle, 4 x beam_angle] = (" +
                 FormatNumber(lid->beam_deg) + ", " + FormatNumber(4 * lid->beam_deg) +
                 "] degrees, got " + Describe(f.Required("field_angle")));
    }
    ratio = field / lid->beam_deg;
  }
  lid->beam_exponent = BeamProfileExponent(ratio);
  if (f.Has("lumens") == f.Has("peak_cd")) {
    f.Fail("give the beam's intensity as exactly one of lumens or peak_cd");
  }
  const double per_peak = BeamLumensPerPeak(lid->beam_deg, lid->beam_exponent);
  if (f.Has("lumens")) {
    lid->lumens = f.Number("lumens", OpenClosed(0, kMaxLumens));
    lid->peak_cd = lid->lumens / per_peak;
  } else {
    lid->peak_cd = f.Number("peak_cd", OpenClosed(0, kMaxPeakCd));
    lid->lumens = lid->peak_cd * per_peak;
    if (lid->lumens > kMaxLumens) f.Fail(f.Required("peak_cd"), "the beam's flux exceeds 2^32 lm");
  }
  if (f.Has("zoom")) {
    const toml::node& node = f.Required("zoom");
    const auto* range = node.as_array();
    if (range == nullptr || range->size() != 2) {
      f.Fail(node, "zoom must be [min_deg, max_deg] (the beam angle's range), got " + Describe(node));
    }
    lid->zoom_min_deg = f.ReadNumber(*range->get(0), "zoom min", angle);
    lid->zoom_max_deg = f.ReadNumber(*range->get(1), "zoom max", angle);
    if (!(lid->zoom_min_deg < lid->zoom_max_deg)) {
      f.Fail(node, "zoom must be [min_deg, max_deg] with min < max, got " + Describe(node));
    }
    if (lid->beam_deg < lid->zoom_min_deg || lid->beam_deg > lid->zoom_max_deg) {
      f.Fail(f.Required("beam_angle"), "beam_angle " + FormatNumber(lid->beam_deg) +
                                           " is outside the zoom range [" +
                                           FormatNumber(lid->zoom_min_deg) + ", " +
                                           FormatNumber(lid->zoom_max_deg) + "]");
    }
  }
  const double narrowest = lid->zooms() ? lid->zoom_min_deg : lid->beam_deg;
  const double peak = lid->lumens / BeamLumensPerPeak(narrowest, lid->beam_exponent);
  if (!(peak <= kMaxPeakCd)) {
    f.Fail("the peak at the narrowest beam angle (" + FormatNumber(narrowest) + " degrees) is " +
           FormatNumber(peak) + " cd, above 2^31 cd");
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
  } else if (type == "beam") {
    f.CheckKeys({"type", "beam_angle", "field_angle", "lumens", "peak_cd", "zoom"});
    ReadBeam(f, &lid);
  } else if (type == "file") {
    f.CheckKeys({"type", "path"});
    ReadFile(f, &lid);
  } else {
    f.Fail(f.Required("type"), "type must be \"isotropic\", \"cos\", \"table\", \"beam\" or \"file\", got " +
                                   Describe(f.Required("type")));
  }
  return lid;
}

}  // namespace relight::baker
