// WriteIes / WriteEulumdat: a PhotometricTable back to text (the project's
// own fixtures in fixtures/photometry/, edited beams from relight-lid).
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "relight/baker/photometric_file.h"

namespace relight::baker {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// Values `per_line` to a line, so readers must follow wrapped lines.
void PutWrapped(const std::vector<double>& values, size_t per_line, std::string* out) {
  for (size_t i = 0; i < values.size(); ++i) {
    *out += Num(values[i]);
    *out += (i + 1) % per_line == 0 || i + 1 == values.size() ? "\n" : " ";
  }
}

}  // namespace

std::string WriteIes(const PhotometricTable& t, const std::string& version) {
  std::string out;
  if (version == "LM-63-1991") {
    out += "IESNA91\n";
  } else if (version == "LM-63-1995" || version == "LM-63-2002") {
    out += "IESNA:" + version + "\n";
  } else if (version == "LM-63-2019") {
    out += "IES:LM-63-2019\n";
  } else if (version != "LM-63-1986") {
    throw std::invalid_argument("WriteIes: unknown version '" + version + "'");
  }
  out += "[TEST] relight analytic fixture\n";
  if (version == "LM-63-2019") out += "[TESTLAB] none\n[ISSUEDATE] 2026-01-01\n";
  out += "[MANUFAC] relight\n";
  out += "[LUMINAIRE] " + (t.luminaire.empty() ? std::string("analytic") : t.luminaire) + "\n";
  if (t.tilt_data.angle_deg.empty()) {
    out += "TILT=NONE\n";
  } else {
    out += "TILT=INCLUDE\n" + std::to_string(t.tilt_data.lamp_geometry) + "\n" +
           std::to_string(t.tilt_data.angle_deg.size()) + "\n";
    PutWrapped(t.tilt_data.angle_deg, 10, &out);
    PutWrapped(t.tilt_data.factor, 10, &out);
  }
  const double multiplier = t.multiplier > 0 ? t.multiplier : 1.0;
  out += "1 " + (t.lamp_lumens > 0 ? Num(t.lamp_lumens) : std::string("-1")) + " " +
         Num(multiplier) + " " + std::to_string(t.gammas()) + " " + std::to_string(t.planes()) +
         " 1 2 0 0 0\n";
  out += "1 1 10\n";
  PutWrapped(t.gamma_deg, 10, &out);
  PutWrapped(t.c_deg, 10, &out);
  for (size_t p = 0; p < t.planes(); ++p) {
    std::vector<double> row;
    for (size_t g = 0; g < t.gammas(); ++g) row.push_back(t.At(p, g) / multiplier);
    PutWrapped(row, 10, &out);
  }
  return out;
}

std::string WriteEulumdat(const PhotometricTable& t) {
  int isym = 0;
  double first_stored = 0;
  switch (t.symmetry) {
    case CSymmetry::kNone: isym = 0; break;
    case CSymmetry::kAxial: isym = 1; break;
    case CSymmetry::kBilateral: isym = 2; break;
    case CSymmetry::kBilateral90: isym = 3; first_stored = 90; break;
    case CSymmetry::kQuadrant: isym = 4; break;
  }
  // Every listed plane: uniform steps Dc over [0, 360).
  std::vector<double> stored = t.c_deg;
  if (t.symmetry == CSymmetry::kNone && !stored.empty() && stored.back() == 360) stored.pop_back();
  double dc = 0;
  int mc = 1;
  if (isym != 1) {
    if (stored.size() < 2) throw std::invalid_argument("WriteEulumdat: needs 2 or more C planes");
    dc = stored[1] - stored[0];
    mc = static_cast<int>(std::lround(360.0 / dc));
    for (size_t p = 0; p < stored.size(); ++p) {
      if (std::fabs(stored[p] - (first_stored + dc * static_cast<double>(p))) > 1e-9) {
        throw std::invalid_argument("WriteEulumdat: C planes must be evenly spaced");
      }
    }
  }
  const double flux = t.lamp_lumens > 0 ? t.lamp_lumens : 1000.0;
  const double dg = t.gammas() > 1 ? t.gamma_deg[1] - t.gamma_deg[0] : 0;
  std::string out;
  const auto line = [&](const std::string& s) { out += s + "\r\n"; };
  line("relight analytic fixture");
  line("1");
  line(std::to_string(isym));
  line(std::to_string(mc));
  line(Num(dc));
  line(std::to_string(t.gammas()));
  line(Num(dg));
  line("relight");
  line(t.luminaire.empty() ? "analytic" : t.luminaire);
  line("0");
  line("analytic.ldt");
  line("2026-01-01");
  for (int k = 0; k < 5; ++k) line("100");
  for (int k = 0; k < 4; ++k) line("0");
  line("100");  // DFF
  line("100");  // LORL
  line("1.0");  // conversion factor
  line("0");    // tilt
  line("1");    // one lamp set
  line("1");
  line("analytic");
  line(Num(flux));
  line("3000");
  line("90");
  line("10");
  for (int k = 0; k < 10; ++k) line("0");
  for (int i = 0; i < mc; ++i) line(Num(isym == 1 ? 0 : dc * i));
  for (double g : t.gamma_deg) line(Num(g));
  for (size_t p = 0; p < t.planes(); ++p) {
    for (size_t g = 0; g < t.gammas(); ++g) line(Num(t.At(p, g) * 1000.0 / flux));
  }
  return out;
}

}  // namespace relight::baker
