// libgpiod 1.6: one request per line for both edges; Poll() drains the event
// file descriptors without blocking and feeds the shared decoder.
#include "relight/hal/gpiod_source.h"

#include <gpiod.h>
#include <poll.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "../change_ring.h"
#include "../gpio_decoder.h"
#include "relight/base/log.h"

namespace relight::hal {

struct GpiodSource::Impl {
  std::string where;
  GpioDecoder decoder;
  ChangeRing queue{1024};
  std::vector<gpiod_chip*> chips;      // opened, one per distinct name
  std::vector<std::string> chip_names;
  std::vector<gpiod_line*> lines;      // per decoder line
  std::vector<pollfd> fds;             // per line, sized at Start()

  explicit Impl(const Patch& patch) : where(patch.where.empty() ? "patch" : patch.where), decoder(patch) {}

  void Close() {
    for (gpiod_line* line : lines) {
      if (line != nullptr) gpiod_line_release(line);
    }
    lines.clear();
    fds.clear();
    for (gpiod_chip* chip : chips) gpiod_chip_close(chip);
    chips.clear();
    chip_names.clear();
  }

  Status OpenChip(const GpioLineUse& use, gpiod_chip** out) {
    for (size_t i = 0; i < chip_names.size(); ++i) {
      if (chip_names[i] == use.chip) {
        *out = chips[i];
        return Status::Ok();
      }
    }
    errno = 0;
    gpiod_chip* chip = gpiod_chip_open_lookup(use.chip.c_str());
    if (chip == nullptr) {
      const int err = errno;
      return Status(err == EACCES || err == EPERM ? StatusCode::kIoError : StatusCode::kNotFound,
                    "gpio: " + where + ": " + use.role + ": cannot open GPIO chip '" + use.chip + "': " +
                        (err == 0                        ? std::string("no chip by that name, path, label or number")
                         : err == ENOTTY || err == ENODEV ? std::string("not a GPIO chip device")
                                                          : std::string(std::strerror(err))));
    }
    chips.push_back(chip);
    chip_names.push_back(use.chip);
    *out = chip;
    return Status::Ok();
  }
};

GpiodSource::GpiodSource(const Patch& patch) : impl_(std::make_unique<Impl>(patch)) {}

GpiodSource::~GpiodSource() { impl_->Close(); }

Status GpiodSource::DoStart() {
  Impl& m = *impl_;
  m.Close();
  const auto& uses = m.decoder.lines();
  for (size_t i = 0; i < uses.size(); ++i) {
    gpiod_chip* chip = nullptr;
    if (Status st = m.OpenChip(uses[i], &chip); !st.ok()) {
      m.Close();
      return st;
    }
    const unsigned count = gpiod_chip_num_lines(chip);
    if (uses[i].line < 0 || static_cast<unsigned>(uses[i].line) >= count) {
      const std::string msg = "gpio: " + m.where + ": " + uses[i].role + ": chip '" + uses[i].chip + "' has no line " +
                              std::to_string(uses[i].line) + " (it has lines 0.." + std::to_string(count) + ")";
      m.Close();
      return Status(StatusCode::kNotFound, msg);
    }
    gpiod_line* line = gpiod_chip_get_line(chip, static_cast<unsigned>(uses[i].line));
    if (line == nullptr || gpiod_line_request_both_edges_events(line, "relightd") != 0) {
      const std::string msg = "gpio: " + m.where + ": " + uses[i].role + ": cannot watch line " +
                              std::to_string(uses[i].line) + " of '" + uses[i].chip + "': " + std::strerror(errno);
      m.Close();
      return Status(StatusCode::kIoError, msg);
    }
    m.lines.push_back(line);
    const int level = gpiod_line_get_value(line);
    m.decoder.SetInitial(static_cast<int>(i), level > 0);
  }
  for (gpiod_line* line : m.lines) m.fds.push_back({gpiod_line_event_get_fd(line), POLLIN, 0});
  Log(LogLevel::kInfo, "gpio: watching %zu lines", m.lines.size());
  return Status::Ok();
}

size_t GpiodSource::DoPoll(int64_t now_us, ParamChange* out, size_t capacity) {
  Impl& m = *impl_;
  std::vector<pollfd>& fds = m.fds;
  if (!fds.empty() && poll(fds.data(), fds.size(), 0) > 0) {
    for (size_t i = 0; i < fds.size(); ++i) {
      if (!(fds[i].revents & POLLIN)) continue;
      gpiod_line_event events[16];
      const int n = gpiod_line_event_read_multiple(m.lines[i], events, 16);
      for (int k = 0; k < n; ++k) {
        // Kernel timestamps are CLOCK_MONOTONIC on Linux >= 5.7 (PITFALLS.md).
        const int64_t t_us = static_cast<int64_t>(events[k].ts.tv_sec) * 1000000 + events[k].ts.tv_nsec / 1000;
        m.decoder.OnEdge(static_cast<int>(i), events[k].event_type == GPIOD_LINE_EVENT_RISING_EDGE, t_us, &m.queue);
      }
    }
  }
  m.decoder.Tick(now_us, &m.queue);
  return m.queue.PopDue(now_us, out, capacity);
}

void GpiodSource::DoStop() { impl_->Close(); }

}  // namespace relight::hal
