// Analytic luminous intensity distributions sampled into PhotometricTables:
// the project's own photometric fixtures (fixtures/photometry/, written by
// `relight-lid fixtures`), one per file format and symmetry case, and the
// malformed variants the reader tests expect clear errors from.
#pragma once

#include <string>
#include <vector>

#include "relight/baker/photometric_file.h"

namespace relight::baker {

// One fixture file: its name, the table and how it is written.
struct PhotometricFixture {
  std::string file_name;  // "ies_1995_bilateral.ies", ...
  std::string version;    // IES version for WriteIes, or "EULUMDAT"
  PhotometricTable table;
  std::string text;       // the file's bytes
};

// The analytic distribution behind a fixture, at (C, gamma) degrees, in cd.
// Kinds: "axial", "oval" (quadrant), "wallwash" (C0-C180), "side" (C90-C270),
// "asym" (no symmetry).
double AnalyticCandela(const std::string& kind, double c_deg, double gamma_deg);

// A floodlight measured in IES type B (type_b_photometry.h has the angles):
// 2000 cd at its peak, 5 degrees up and `h_peak_deg` to the right, falling
// as Gaussians of 25 degrees across and 12 up and down; at (H, V) degrees.
double AnalyticTypeBFlood(double h_deg, double v_deg, double h_peak_deg);
// Its LM-63-2002 type B file, 2.5-degree steps: H -90..90 with the peak
// 10 degrees to the right, or (`symmetric`) H 0..90 with the peak on the axis.
std::string TypeBFloodIes(bool symmetric);
inline constexpr const char* kTypeBFloodFile = "ies_2002_type_b_flood.ies";

// Every well-formed fixture, deterministic.
std::vector<PhotometricFixture> PhotometricFixtures();

// Malformed variants: file name -> text, each for the reader to reject with
// the message part in `expect`.
struct MalformedFixture {
  std::string file_name;
  std::string text;
  std::string expect;  // part of the error message
  int line = 0;        // the line the error must name (0: not checked)
};
std::vector<MalformedFixture> MalformedPhotometricFixtures();

}  // namespace relight::baker
