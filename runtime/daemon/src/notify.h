// relightd under systemd (runtime/daemon/systemd/relightd.service,
// docs/security.md): readiness and the watchdog through libsystemd's
// sd_notify. READY=1 goes out once the first frame has reached the sinks
// (so `systemctl start` returns when a picture is there); WATCHDOG=1 after
// frames, at most every quarter of WatchdogSec, so a frame loop that stalls
// stops pinging and systemd restarts it; STOPPING=1 on the way out.
// Without $NOTIFY_SOCKET (not started by systemd) every call does nothing.
//
// Thread safety: one thread (the frame loop's observer).
#pragma once

#include <cstdint>

namespace relight::daemon {

class SystemdNotifier {
 public:
  // Reads $NOTIFY_SOCKET and $WATCHDOG_USEC (sd_watchdog_enabled) once.
  SystemdNotifier();

  // Call after every frame; `now_us` on the monotonic clock.
  void OnFrame(int64_t now_us);
  void Stopping();

  bool ready_sent() const { return ready_sent_; }
  int64_t watchdog_period_us() const { return watchdog_period_us_; }  // 0: no watchdog

 private:
  bool ready_sent_ = false;
  int64_t watchdog_period_us_ = 0;  // ping interval: WatchdogSec / 4
  int64_t last_ping_us_ = 0;
};

}  // namespace relight::daemon
