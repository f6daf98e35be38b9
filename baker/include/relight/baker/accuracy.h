// Accuracy of the run-time engine against the float64 reference solve, on the
// same scene, mesh and fixture settings. Every accuracy figure in docs/ comes
// from here (via relight-accuracy or the integration tests).
#pragma once

#include <string>
#include <vector>

#include "relight/baker/baker.h"
#include "relight/engine/engine.h"

namespace relight::baker {

struct AccuracyFigures {
  double peak = 0;      // reference peak over receivers and channels (cd/m^2 or lux)
  double max_rel = 0;   // max |engine - reference| / peak
  double mean_rel = 0;  // mean |engine - reference| / peak over receivers and channels
  size_t worst_index = 0;  // receiver of the max error
};

struct AccuracyReport {
  AccuracyFigures vertices;  // luminance at mesh vertices
  AccuracyFigures grids;     // illuminance at calculation-grid points (all grids)
};

// Puts `settings` (one per luminaire, scene order) into the engine.
Status ApplySettings(const std::vector<FixtureSetting>& settings, Engine* engine);

// Runs the engine at `settings` and compares with the reference. Vertices are
// compared with reference.vertex_luminance when the bake's luminaires use the
// exact direct term, with vertex_luminance_patch_average when they are all in
// SH (each mode against what it approximates; see baker.h).
AccuracyReport CompareWithReference(Engine* engine, const ReferenceResult& reference,
                                    const std::vector<FixtureSetting>& settings);

}  // namespace relight::baker
