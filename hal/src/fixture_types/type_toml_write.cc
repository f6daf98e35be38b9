// FixtureType -> the TOML form type_toml.cc reads, in the order a person
// edits it: the type's keys, its [[channel]]s (the order that mode channel
// lists index), then its [[mode]]s. Strings go through toml++'s formatter,
// which escapes quotes, backslashes and control characters; numbers are
// written here (toml++ tables sort keys, which would put `name` last).
//
// Not written: DmxChannel::line and DmxMode::line (where the new file puts
// them), FixtureType::where (named in the header comment only) and
// DmxChannel::ignored_why (a comment after an ignored channel's function).
#include <toml++/toml.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "fixture_types/type_common.h"
#include "relight/hal/dmx/fixture_type.h"

namespace relight::hal {
namespace {

// A basic string ("..."): escapes, no literal or multi-line forms.
std::string Quoted(const std::string& s) {
  std::ostringstream out;
  out << toml::toml_formatter{toml::value<std::string>{s}, toml::format_flags::allow_unicode_strings};
  return out.str();
}

// Comment text on one line: control characters become spaces.
std::string CommentText(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  }
  return s;
}

// Degrees of a Q16.16 angle with the fewest decimals that read back to the
// same integer through type_toml.cc's lround(v * 65536): "7.3", not
// "7.29998779296875" (Q16 of the .qxf's 7.3). q / 65536 is a double exactly
// and needs at most 16 decimals, so the loop always ends with a match.
std::string DegreesText(int32_t q16) {
  const double exact = q16 / 65536.0;
  char buf[64];
  for (int decimals = 1; decimals <= 16; ++decimals) {
    const auto end = std::to_chars(buf, buf + sizeof buf, exact, std::chars_format::fixed, decimals).ptr;
    double back = 0.0;
    std::from_chars(buf, end, back);
    if (std::lround(back * 65536.0) == q16 || decimals == 16) return std::string(buf, end);
  }
  return {};  // not reached
}

std::string ColorText(const Rgb8& c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
  return buf;
}

// pan_range_deg, tilt_range_deg, beam_deg of the type or of a mode; 0 = not given.
void WritePhysical(std::ostringstream& out, int pan, int tilt, int32_t beam_min, int32_t beam_max) {
  if (pan != 0) out << "pan_range_deg = " << pan << "\n";
  if (tilt != 0) out << "tilt_range_deg = " << tilt << "\n";
  if (beam_min != 0 || beam_max != 0) {
    out << "beam_deg = [" << DegreesText(beam_min) << ", " << DegreesText(beam_max) << "]  # narrowest, widest\n";
  }
}

void WriteChannel(std::ostringstream& out, const DmxChannel& c) {
  out << "[[channel]]\nname = " << Quoted(c.name) << "\nfunction = " << Quoted(DmxFunctionName(c.function));
  if (c.function == DmxFunction::kIgnored && !c.ignored_why.empty() && c.ignored_why != kTomlIgnoredWhy) {
    out << "  # " << CommentText(c.ignored_why);
  }
  out << "\n";
  if (c.function == DmxFunction::kZoom || c.zoom_big_to_small) {
    out << "big_to_small = " << (c.zoom_big_to_small ? "true" : "false") << "\n";
  }
  if (!c.slots.empty()) {
    out << "slots = [\n";
    for (const WheelSlot& s : c.slots) {
      out << "  { min = " << int{s.range.min} << ", max = " << int{s.range.max} << ", color = \"" << ColorText(s.color)
          << "\" },\n";
    }
    out << "]\n";
  }
  if (!c.closed.empty()) {
    out << "closed = [";
    for (size_t i = 0; i < c.closed.size(); ++i) {
      out << (i ? ", " : "") << "[" << int{c.closed[i].min} << ", " << int{c.closed[i].max} << "]";
    }
    out << "]\n";
  }
}

// channels = [...], wrapped before 100 columns under the first name.
void WriteModeChannels(std::ostringstream& out, const FixtureType& type, const DmxMode& m) {
  const std::string head = "channels = [";
  const std::string indent(head.size(), ' ');
  out << head;
  if (m.channels.empty()) out << "]";  // which the reader refuses, as ParseQxf does
  size_t column = head.size();
  for (size_t i = 0; i < m.channels.size(); ++i) {
    const std::string name = Quoted(type.channels[static_cast<size_t>(m.channels[i])].name);
    const std::string sep = i + 1 < m.channels.size() ? "," : "]";
    if (i > 0) {
      if (column + 1 + name.size() + sep.size() > 100) {
        out << "\n" << indent;
        column = indent.size();
      } else {
        out << " ";
        ++column;
      }
    }
    out << name << sep;
    column += name.size() + sep.size();
  }
  out << "\n";
}

}  // namespace

std::string FixtureTypeToToml(const FixtureType& type) {
  std::ostringstream out;
  out << "# A DMX fixture type in relight's TOML form (docs/dmx.md \"Adding a fixture type\")";
  if (!type.where.empty()) out << ",\n# written from " << CommentText(type.where);
  out << ".\n";
  out << "manufacturer = " << Quoted(type.manufacturer) << "\n";
  out << "model = " << Quoted(type.model) << "\n";
  if (!type.type.empty()) out << "type = " << Quoted(type.type) << "\n";
  WritePhysical(out, type.pan_range_deg, type.tilt_range_deg, type.beam_min_q16, type.beam_max_q16);
  out << "\n";
  for (const DmxChannel& c : type.channels) WriteChannel(out, c);
  for (const DmxMode& m : type.modes) {
    out << "\n[[mode]]\nname = " << Quoted(m.name) << "\n";
    WritePhysical(out, m.pan_range_deg, m.tilt_range_deg, m.beam_min_q16, m.beam_max_q16);
    WriteModeChannels(out, type, m);
  }
  return out.str();
}

}  // namespace relight::hal
