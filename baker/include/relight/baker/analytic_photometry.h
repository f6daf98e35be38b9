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
