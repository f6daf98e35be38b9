// The reference run of relight-bake (--reference): --set arguments applied to
// the scene's default settings, and the float64 result written as CSV.
#pragma once

#include <string>
#include <vector>

#include "mesher.h"
#include "relight/baker/baker.h"
#include "relight/baker/scene.h"

namespace relight::bake_cli {

// Applies `sets` ("fixture.param=value") to `settings` (one per luminaire of
// `scene`); false with *error naming the argument and what is wrong. A zoom
// past the beam's range is clamped, as the engine does, with a note on stderr.
bool ApplySets(const baker::Scene& scene, const std::vector<std::string>& sets,
               std::vector<baker::FixtureSetting>* settings, std::string* error);

// Writes `text` to a temporary file beside `path`, then renames it into place.
bool WriteFileAtomic(const std::string& path, const std::string& text, std::string* error);

// index,x_m,y_m,z_m,R,G,B (cd/m^2) per vertex.
std::string VerticesCsv(const baker::Mesh& mesh, const baker::ReferenceResult& ref);
// grid,point,x_m,y_m,z_m,E_total_lux,E_direct_lux (photometric Y) per grid point.
std::string GridsCsv(const baker::Scene& scene, const baker::ReferenceResult& ref);

}  // namespace relight::bake_cli
