#include "relight/baker/accuracy.h"

#include <algorithm>
#include <cmath>

namespace relight::baker {
namespace {

Q16_16 Degrees(double d) {
  return Q16_16::FromRaw(static_cast<int32_t>(std::llround(d * 65536.0)));
}
Q1_15 Level(double v) {
  return Q1_15::FromRaw(static_cast<int16_t>(std::lround(std::clamp(v, 0.0, 1.0) * 32767.0)));
}

// Compares engine output (LightQ12, 3 per receiver) with reference RGB values.
// The reference and the engine cover the same receivers (both come from the
// same bake); the loop stops at the shorter one all the same.
template <LightQuantity Q>
void Accumulate(RgbLightView<Q> engine, const std::vector<Rgb>& reference,
                std::vector<double>* errors, double* peak) {
  const size_t count = std::min<size_t>(reference.size(), engine.receivers());
  for (size_t r = 0; r < count; ++r) {
    for (uint32_t c = 0; c < 3; ++c) {
      const double got = engine.at(static_cast<uint32_t>(r), c).raw() / 4096.0;
      errors->push_back(std::abs(got - reference[r][c]));
      *peak = std::max(*peak, std::abs(reference[r][c]));
    }
  }
}

AccuracyFigures Summarise(const std::vector<double>& errors, double peak) {
  AccuracyFigures f;
  f.peak = peak;
  if (errors.empty() || peak <= 0) return f;
  double sum = 0;
  for (size_t i = 0; i < errors.size(); ++i) {
    sum += errors[i];
    if (errors[i] > f.max_rel * peak) {
      f.max_rel = errors[i] / peak;
      f.worst_index = i / 3;
    }
  }
  f.mean_rel = sum / static_cast<double>(errors.size()) / peak;
  return f;
}

}  // namespace

Status ApplySettings(const std::vector<FixtureSetting>& settings, Engine* engine) {
  if (static_cast<int>(settings.size()) != engine->luminaire_count()) {
    return Status(
        StatusCode::kInvalidArgument,
        StrFormat("%zu settings for %d luminaires", settings.size(), engine->luminaire_count()));
  }
  for (int i = 0; i < engine->luminaire_count(); ++i) {
    const FixtureSetting& s = settings[i];
    RELIGHT_RETURN_IF_ERROR(engine->SetPanTilt(i, Degrees(s.pan_deg), Degrees(s.tilt_deg)));
    const Q16_16 roll = s.roll_deg ? Degrees(*s.roll_deg)
                                   : Q16_16::FromRaw(engine->bake().luminaires[i].roll);
    RELIGHT_RETURN_IF_ERROR(engine->SetRoll(i, roll));
    const BakeZoom& zoom = engine->bake().luminaires[i].zoom;
    if (zoom.present()) {
      const Q16_16 angle = s.zoom_deg ? Degrees(*s.zoom_deg) : Q16_16::FromRaw(zoom.default_deg);
      RELIGHT_RETURN_IF_ERROR(engine->SetZoom(i, angle));
    }
    RELIGHT_RETURN_IF_ERROR(engine->SetDimmer(i, Level(s.dimmer)));
    RELIGHT_RETURN_IF_ERROR(
        engine->SetColour(i, Level(s.colour[0]), Level(s.colour[1]), Level(s.colour[2])));
  }
  return Status::Ok();
}

AccuracyReport CompareWithReference(Engine* engine, const ReferenceResult& reference,
                                    const std::vector<FixtureSetting>& settings) {
  const Status st = ApplySettings(settings, engine);
  RELIGHT_CHECK(st.ok());
  engine->Update();

  bool all_in_sh = !engine->bake().luminaires.empty();
  for (const BakeLuminaire& lum : engine->bake().luminaires) {
    all_in_sh = all_in_sh && lum.direct_mode == DirectMode::kAllInSh;
  }
  AccuracyReport report;
  std::vector<double> errors;
  double peak = 0;
  Accumulate(engine->vertex_luminance(),
             all_in_sh ? reference.vertex_luminance_patch_average : reference.vertex_luminance,
             &errors, &peak);
  report.vertices = Summarise(errors, peak);

  errors.clear();
  peak = 0;
  for (size_t g = 0; g < reference.grid_illuminance.size(); ++g) {
    Accumulate(engine->grid_illuminance(static_cast<int>(g)), reference.grid_illuminance[g],
               &errors, &peak);
  }
  report.grids = Summarise(errors, peak);
  return report;
}

}  // namespace relight::baker
