// DMX replay: the recording parser and the source that plays it.
#include <cstring>
#include <sstream>

#include "../bounded_file.h"
#include "../timed_lines.h"
#include "dmx_changes.h"
#include "relight/hal/dmx/dmx_replay_source.h"

namespace relight::hal {
namespace {

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// A decimal integer in [lo, hi] filling the whole of `s`.
bool ParseInt(const std::string& s, int64_t lo, int64_t hi, int64_t* out) {
  if (s.empty() || s.size() > 18) return false;
  int64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  if (v < lo || v > hi) return false;
  *out = v;
  return true;
}

}  // namespace

Status ParseDmxRecording(const std::string& text, const std::string& where, DmxRecording* out) {
  DmxRecording rec;
  TimedLines lines(text, where, kMaxDmxReplayLineBytes);
  const auto fail = [&](const std::string& why) { return lines.Fail(why); };
  int64_t last_us = 0;
  std::istringstream words;
  Status status;
  while (lines.Next(&words, &status)) {
    std::string time_text, universe_text, item;
    if (!(words >> time_text)) continue;  // blank or comment
    int64_t time_us = 0, universe = 0;
    if (!ParseInt(time_text, 0, int64_t{1} << 50, &time_us)) {
      return fail("expected a time in microseconds (an integer, 0 or more) at the start of the line, got '" +
                  time_text + "'");
    }
    if (time_us < last_us) return fail("time " + time_text + " us goes backwards (times must not decrease)");
    last_us = time_us;
    if (!(words >> universe_text) || !ParseInt(universe_text, 0, 0x7fffffff, &universe)) {
      return fail("expected a universe number after the time, got '" + universe_text + "'");
    }
    DmxReplayFrame frame;
    frame.time_us = time_us;
    frame.universe = static_cast<unsigned>(universe);
    frame.first_run = static_cast<uint32_t>(rec.runs.size());
    while (words >> item) {
      const size_t eq = item.find('=');
      int64_t slot = 0;
      if (eq == std::string::npos || !ParseInt(item.substr(0, eq), 1, kDmxSlots, &slot)) {
        return fail("'" + item + "': expected SLOT=HEX with SLOT in 1..512, e.g. 1=ff00");
      }
      const std::string hex = item.substr(eq + 1);
      if (hex.empty() || hex.size() % 2 != 0) {
        return fail("'" + item + "': the bytes must be an even number of hex digits (two per slot)");
      }
      const size_t count = hex.size() / 2;
      if (slot - 1 + static_cast<int64_t>(count) > kDmxSlots) {
        return fail("'" + item + "': " + std::to_string(count) + " bytes from slot " + std::to_string(slot) +
                    " pass slot 512");
      }
      DmxReplayRun run;
      run.slot = static_cast<uint16_t>(slot);
      run.count = static_cast<uint16_t>(count);
      run.offset = static_cast<uint32_t>(rec.bytes.size());
      for (size_t k = 0; k < count; ++k) {
        const int hi = HexDigit(hex[2 * k]), lo = HexDigit(hex[2 * k + 1]);
        if (hi < 0 || lo < 0) return fail("'" + item + "': '" + hex + "' is not hex");
        rec.bytes.push_back(static_cast<uint8_t>(hi << 4 | lo));
      }
      rec.runs.push_back(run);
    }
    frame.run_count = static_cast<uint32_t>(rec.runs.size()) - frame.first_run;
    if (frame.run_count == 0) return fail("a frame needs at least one SLOT=HEX after its universe");
    rec.frames.push_back(frame);
  }
  RELIGHT_RETURN_IF_ERROR(status);
  *out = std::move(rec);
  return Status::Ok();
}

struct DmxReplaySource::Impl {
  DmxPatch patch;
  std::string path;
  DmxChanges changes;
  DmxRecording rec;
  size_t next = 0;
  // Per universe the patch uses: its 512 slots as the recording left them
  // and the frame length so far. Sized at Start.
  std::vector<unsigned> universes;
  std::vector<std::vector<uint8_t>> slots;
  std::vector<size_t> length;

  Impl(DmxPatch p, std::string file) : patch(std::move(p)), path(std::move(file)), changes(patch) {}
};

DmxReplaySource::DmxReplaySource(DmxPatch patch, std::string path)
    : impl_(std::make_unique<Impl>(std::move(patch), std::move(path))) {}
DmxReplaySource::~DmxReplaySource() = default;

int64_t DmxReplaySource::duration_us() const {
  return impl_->rec.frames.empty() ? 0 : impl_->rec.frames.back().time_us;
}

Status DmxReplaySource::DoStart() {
  Impl& m = *impl_;
  std::string text;
  RELIGHT_RETURN_IF_ERROR(ReadConfigFile(m.path, "DMX replay", &text, kMaxDmxRecordingBytes));
  RELIGHT_RETURN_IF_ERROR(ParseDmxRecording(text, m.path, &m.rec));
  m.universes.clear();
  for (const DmxFixturePatch& fp : m.patch.fixtures) {
    bool known = false;
    for (unsigned u : m.universes) known = known || u == static_cast<unsigned>(fp.universe);
    if (!known) m.universes.push_back(static_cast<unsigned>(fp.universe));
  }
  m.slots.assign(m.universes.size(), std::vector<uint8_t>(kDmxSlots, 0));
  m.length.assign(m.universes.size(), 0);
  m.next = 0;
  return Status::Ok();
}

size_t DmxReplaySource::DoPoll(int64_t now_us, ParamChange* out, size_t capacity) {
  Impl& m = *impl_;
  // Every frame due is applied in order (the decoder sees each one, so a
  // 16-bit value is taken only from a frame holding both of its bytes);
  // then the changes are what differs from the last poll.
  while (m.next < m.rec.frames.size() && m.rec.frames[m.next].time_us <= now_us) {
    const DmxReplayFrame& frame = m.rec.frames[m.next++];
    size_t u = 0;
    while (u < m.universes.size() && m.universes[u] != frame.universe) ++u;
    if (u == m.universes.size()) continue;  // not patched
    for (uint32_t r = frame.first_run; r < frame.first_run + frame.run_count; ++r) {
      const DmxReplayRun& run = m.rec.runs[r];
      std::memcpy(&m.slots[u][run.slot - 1u], &m.rec.bytes[run.offset], run.count);
      const size_t end = size_t{run.slot} - 1 + run.count;
      if (end > m.length[u]) m.length[u] = end;
    }
    m.changes.OnFrame(frame.universe, m.slots[u].data(), m.length[u], frame.time_us);
  }
  return m.changes.Collect(now_us, out, capacity);
}

bool DmxReplaySource::DoFinished() const { return impl_->next >= impl_->rec.frames.size(); }

}  // namespace relight::hal
