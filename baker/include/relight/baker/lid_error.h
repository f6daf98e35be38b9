// How well a truncated (and windowed) real-SH series approximates a LID, and
// the smallest SH degree that meets an error target (relight-bake
// --lid-error). Two measures, relative to the LID itself:
//  * kL2: the L2 norm over the sphere, || I - I_N || / || I ||: pointwise
//    fidelity, what the all-in-SH mode shows directly in the picture.
//  * kZonalFlux: the fraction of the luminaire's flux that the series puts
//    into the wrong 10 x 10 degree (C, gamma) cell,
//      1/2 sum_cells | Phi_cell(I_N) - Phi_cell(I) | / Phi,
//    what the indirect basis needs: interreflection only sees how much flux
//    lands on each surface patch, never the beam's detail within a patch.
//    The default of the exact-direct mode, whose SH carries indirect light only.
// I_N = sum_{l<=N} w_l sum_m c_lm Y_lm with a window w_l against ringing.
#pragma once

#include <string>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

enum class ShWindow {
  kNone,     // w_l = 1: the least-squares series (relight's exact-direct default)
  kSigma,    // Dobashi Eq. 13 (Lanczos' sigma factor): sinc(pi l / (N + 1))
  kHanning,  // (1 + cos(pi l / (N + 1))) / 2
  kLanczos,  // sinc(pi l / (N + 1))^2: the sigma factor applied twice, a steeper roll-off
  kSloan,    // Sloan's Laplacian-penalty window 1 / (1 + lambda (l (l + 1))^2), lambda so w_N = 1/2
};
const char* ShWindowName(ShWindow window);
// Parses "none", "sigma", "hanning", "lanczos", "sloan"; throws std::invalid_argument.
ShWindow ParseShWindow(const std::string& name);
double ShWindowFactor(ShWindow window, int degree, int l);

enum class LidErrorMeasure { kL2, kZonalFlux };
const char* LidErrorMeasureName(LidErrorMeasure measure);

// A LID sampled on fine rings of gamma (Simpson) and C (midpoints), with its
// SH coefficients up to kMaxShDegree in the fixture frame (bake.h); then any
// truncated, windowed series can be measured against it.
class LidErrorModel {
 public:
  explicit LidErrorModel(const Lid& lid);
  double Error(int degree, ShWindow window, LidErrorMeasure measure) const;
  // The series' lowest value over the sphere relative to the LID's peak
  // (ringing below zero shows as a negative number).
  double MinimumRelative(int degree, ShWindow window) const;
  const std::vector<double>& coefficients() const { return coef_; }

 private:
  // I_N on every ring sample, into `out` (rings x steps).
  void Synthesise(int degree, ShWindow window, std::vector<double>* out) const;
  std::vector<double> samples_;  // rings x steps, the LID
  std::vector<double> ring_y_;   // rings x terms: Y_lm at C = 0 (q_l^m sin^m gamma)
  std::vector<double> coef_;     // (kMaxShDegree + 1)^2
  double peak_ = 0;
};

struct DegreeChoice {
  int degree = 0;
  double error = 0;  // achieved
  bool met = false;  // false: even kMaxShDegree misses the target
};
// The smallest degree in [min_degree, kMaxShDegree] whose error is <= target.
DegreeChoice ChooseShDegree(const LidErrorModel& model, double target, ShWindow window,
                            LidErrorMeasure measure, int min_degree = 1);

// relight-bake --lid-error: each luminaire's sh_degree replaced by the
// smallest degree whose series meets `target`, with the window the bake will
// use (the sigma factor when the series is damped: the all-in-SH mode or
// `sigma = true`; none otherwise) and the mode's measure (zonal flux for the
// exact-direct mode, L2 for all-in-SH). One line per luminaire.
struct LuminaireDegree {
  std::string name;
  int old_degree = 0;
  DegreeChoice choice;
  ShWindow window = ShWindow::kNone;
  LidErrorMeasure measure = LidErrorMeasure::kZonalFlux;
};
// One luminaire's degree for `target` (sets it, marks it given).
LuminaireDegree ChooseLuminaireDegree(Luminaire* lum, double target, DirectModeKind mode);
// A zooming beam is measured at its narrowest angle (the one that needs the
// highest degree). Marks every degree as given.
std::vector<LuminaireDegree> ApplyLidErrorTarget(Scene* scene, double target, DirectModeKind mode);

// The zonal flux (exact direct) or L2 (all in SH) target a zooming beam's
// degree is chosen for when the scene gives no sh_degree (zoom_degree.cc).
inline constexpr double kZoomDegreeTarget = 0.02;
// The LID a luminaire's degree must serve: a zooming beam at its narrowest
// angle, any other LID as it is.
Lid NarrowestLid(const Lid& lid);
// Every zooming beam whose sh_degree the scene did not give gets the smallest
// degree whose series meets kZoomDegreeTarget at its narrowest angle, with
// the window and measure of ApplyLidErrorTarget; one entry per such luminaire.
std::vector<LuminaireDegree> ChooseZoomDegrees(Scene* scene, DirectModeKind mode);

}  // namespace relight::baker
