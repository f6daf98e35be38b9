// Real luminaires: manufacturers' photometric files, IES LM-63 (1986, 1991,
// 1995, 2002, 2019 headers) and EULUMDAT (.ldt), read into one candela table
// over (C, gamma) in the file's own angles (float64, candela, every
// multiplier applied). Readers throw SceneError naming the file, the line and
// what was expected; writers produce files the readers accept.
//
// Photometric angles (type C, both formats): gamma is the angle from the
// luminaire's nadir (its beam axis, gamma 0) towards its zenith (180); C is
// the azimuth about that axis, counter-clockwise seen from behind the
// luminaire looking along its beam (from above a hanging luminaire), C 0 the
// luminaire's length / C0 plane. runtime/bake/include/relight/bake/bake.h places this
// frame in the world (mounting, pan, tilt, roll).
#pragma once

#include <string>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

enum class PhotometricFormat { kIes, kEulumdat };

// Which C planes a file stores and how the others follow from them.
enum class CSymmetry {
  kAxial,        // one plane, the same at every C
  kQuadrant,     // C 0..90, mirrored about the C0-C180 and C90-C270 planes
  kBilateral,    // C 0..180, mirrored about the C0-C180 plane: I(C) = I(360 - C)
  kBilateral90,  // C 90..270, mirrored about the C90-C270 plane: I(C) = I(180 - C)
  kNone,         // C 0..360 (a last plane below 360 wraps round to C 0)
};
const char* CSymmetryName(CSymmetry symmetry);

// IES TILT=INCLUDE (or TILT=<file>) data: candela multipliers against the
// lamp's tilt. Read and checked; relight uses the distribution as measured.
struct TiltData {
  int lamp_geometry = 0;  // 1 vertical base-up/down, 2 horizontal along C90, 3 along C0
  std::vector<double> angle_deg;
  std::vector<double> factor;
};

struct PhotometricTable {
  std::string path;  // the file, for messages
  PhotometricFormat format = PhotometricFormat::kIes;
  std::string version;  // "LM-63-1986" ... "LM-63-2019", "EULUMDAT"
  std::string tilt;     // IES: "NONE", "INCLUDE" or the TILT file's name
  // "C", or "B" for an IES type B (floodlight) file, whose table here is
  // already resampled to (C, gamma) (type_b_photometry.h).
  std::string photometric_type = "C";
  TiltData tilt_data;
  CSymmetry symmetry = CSymmetry::kAxial;
  std::vector<double> c_deg;      // stored planes, strictly increasing
  std::vector<double> gamma_deg;  // strictly increasing, within [0, 180]
  std::vector<double> candela;    // [plane * gammas + g], cd
  double lamp_lumens = 0;         // rated lamp flux in total, lm; 0 = absolute photometry
  double multiplier = 1;          // applied to the file's numbers to give candela
  std::string luminaire;          // [LUMINAIRE] / [LUMCAT] / EULUMDAT name, for reports

  size_t planes() const { return c_deg.size(); }
  size_t gammas() const { return gamma_deg.size(); }
  double At(size_t plane, size_t g) const { return candela[plane * gamma_deg.size() + g]; }
  // Candela at (C, gamma) in degrees: C folded onto the stored planes by the
  // symmetry, bilinear in (C, gamma) between the file's own angles, 0 outside
  // the gamma range the file covers. gamma is taken modulo 360 and folded
  // (gamma and 360 - gamma on the opposite C are one direction).
  double Evaluate(double c_deg, double gamma_deg) const;
  double PeakCandela() const;
  // Luminous flux of the interpolated distribution, lm (fine quadrature).
  double LuminousFlux() const;
};

// The file's table expanded to the full circle: C from 0 to 360 inclusive
// (the plane at 360 repeats the one at 0), every mirrored plane written out,
// so that bilinear interpolation in it equals PhotometricTable::Evaluate.
// This is what a bake stores for a luminaire that is not axisymmetric.
struct FullCircleTable {
  std::vector<double> c_deg;      // 0 first, 360 last, strictly increasing
  std::vector<double> gamma_deg;  // as the file
  std::vector<double> candela;    // [plane * gammas + g]
  double Evaluate(double c_deg, double gamma_deg) const;
};
FullCircleTable ExpandToFullCircle(const PhotometricTable& table);

// Parse text already in memory; `path` names it in messages (and places a
// TILT=<file> next to it).
PhotometricTable ParseIes(const std::string& text, const std::string& path);
PhotometricTable ParseEulumdat(const std::string& text, const std::string& path);
// Reads `path` and picks the reader by extension (.ies / .ldt, any case).
PhotometricTable LoadPhotometricFile(const std::string& path);

// The scene's Lid for a file's table: one C plane gives an axisymmetric
// kTable (gamma and candela as the file has them), anything else kCGamma.
Lid MakeLid(PhotometricTable table);
// LoadPhotometricFile then MakeLid.
Lid LoadLid(const std::string& path);

// Writers. IES: `version` one of "LM-63-1986", "LM-63-1991", "LM-63-1995",
// "LM-63-2002", "LM-63-2019"; TILT=INCLUDE when table.tilt_data has angles.
// The table must be type C with the symmetry its angles imply. Candela are
// written with the multiplier divided out again.
std::string WriteIes(const PhotometricTable& table, const std::string& version);
// EULUMDAT: the table's symmetry picks Isym; intensities in cd/klm against
// table.lamp_lumens (1000 lm when 0).
std::string WriteEulumdat(const PhotometricTable& table);

}  // namespace relight::baker
