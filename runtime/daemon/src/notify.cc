#include "notify.h"

#include <systemd/sd-daemon.h>

#include <cstdint>

namespace relight::daemon {

SystemdNotifier::SystemdNotifier() {
  uint64_t usec = 0;
  // > 0 only when systemd set WATCHDOG_USEC for this very process.
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
    // A quarter of the timeout: a late frame or two never trips it, a stall does.
    watchdog_period_us_ = static_cast<int64_t>(usec / 4);
  }
}

void SystemdNotifier::OnFrame(int64_t now_us) {
  if (!ready_sent_) {
    sd_notify(0, "READY=1\nSTATUS=first frame out; rendering");
    ready_sent_ = true;
    last_ping_us_ = now_us;
    if (watchdog_period_us_ > 0) sd_notify(0, "WATCHDOG=1");
    return;
  }
  if (watchdog_period_us_ > 0 && now_us - last_ping_us_ >= watchdog_period_us_) {
    sd_notify(0, "WATCHDOG=1");
    last_ping_us_ = now_us;
  }
}

void SystemdNotifier::Stopping() { sd_notify(0, "STOPPING=1"); }

}  // namespace relight::daemon
