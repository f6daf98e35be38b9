// Modbus client poller: its own thread and libmodbus context; one read of
// the span of mapped registers per period.
#include <modbus/modbus.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <thread>

#include "../register_input.h"
#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/hal/modbus_poller.h"

namespace relight::hal {

struct ModbusPoller::Impl {
  ModbusPollerConfig config;
  RegisterInput input;
  std::vector<int> target;  // per map entry: our register address
  int first = 0, count = 0;  // span read from the peer
  std::thread thread;
  std::mutex mutex;
  std::condition_variable wake;
  bool stop = false;  // guarded by mutex
  std::atomic<uint32_t> reads_ok{0}, reads_failed{0}, connects{0};
  std::atomic<bool> connected{false};

  Impl(ModbusPollerConfig c, const RegisterMap& map, std::vector<uint16_t> initial)
      : config(std::move(c)), input(map, std::move(initial)) {}

  // Sleeps up to `ms`; false if Stop() came.
  bool Sleep(int64_t ms) {
    std::unique_lock<std::mutex> lock(mutex);
    return !wake.wait_for(lock, std::chrono::milliseconds(ms), [&] { return stop; });
  }

  void Run() {
    const std::string peer = config.host + ":" + std::to_string(config.port);
    modbus_t* ctx = modbus_new_tcp(config.host.c_str(), config.port);
    if (ctx == nullptr) {
      Log(LogLevel::kError, "modbus-poller: %s: cannot create a libmodbus context", peer.c_str());
      return;
    }
    modbus_set_slave(ctx, config.unit_id);
    modbus_set_response_timeout(ctx, static_cast<uint32_t>(config.timeout_ms / 1000),
                                static_cast<uint32_t>(config.timeout_ms % 1000) * 1000);
    const int64_t period_us = 1000000 / config.rate_hz;
    int64_t backoff_ms = 100;
    bool lost_logged = false;  // "logs once": one line per outage
    std::vector<uint16_t> values(static_cast<size_t>(count));
    int64_t next_us = MonotonicUs();
    for (;;) {
      if (!connected.load()) {
        if (modbus_connect(ctx) != 0) {
          if (!lost_logged) {
            Log(LogLevel::kWarning, "modbus-poller: cannot reach %s (%s); keeping the last state, retrying",
                peer.c_str(), std::strerror(errno));
            lost_logged = true;
          }
          if (!Sleep(backoff_ms)) break;
          backoff_ms = backoff_ms * 2 > config.backoff_max_ms ? config.backoff_max_ms : backoff_ms * 2;
          continue;
        }
        connected.store(true);
        connects.fetch_add(1);
        backoff_ms = 100;
        Log(LogLevel::kInfo, "modbus-poller: connected to %s, reading %d registers from %d at %d Hz", peer.c_str(),
            count, first, config.rate_hz);
        lost_logged = false;
        next_us = MonotonicUs();
      }
      const int rc = modbus_read_registers(ctx, first, count, values.data());
      const int64_t arrival_us = MonotonicUs();
      if (rc == count) {
        reads_ok.fetch_add(1);
        for (size_t i = 0; i < config.map.size(); ++i) {
          input.Write(target[i], 1, &values[static_cast<size_t>(config.map[i].peer_register - first)], arrival_us);
        }
      } else {
        reads_failed.fetch_add(1);
        const int err = errno;
        if (err > MODBUS_ENOBASE && err < MODBUS_ENOBASE + 16) {
          // The peer answered with an exception: it is there, our map is wrong.
          if (!lost_logged) {
            Log(LogLevel::kWarning, "modbus-poller: %s refuses registers %d..%d: %s", peer.c_str(), first,
                first + count - 1, modbus_strerror(err));
            lost_logged = true;
          }
        } else {
          Log(LogLevel::kWarning, "modbus-poller: lost %s (%s); keeping the last state, reconnecting", peer.c_str(),
              modbus_strerror(err));
          lost_logged = true;
          modbus_close(ctx);
          connected.store(false);
          continue;
        }
      }
      next_us += period_us;
      const int64_t now_us = MonotonicUs();
      if (next_us < now_us) next_us = now_us;  // fell behind: do not burst
      if (!Sleep((next_us - now_us) / 1000)) break;
    }
    modbus_close(ctx);
    modbus_free(ctx);
    connected.store(false);
  }

  void Shutdown() {
    {
      std::lock_guard<std::mutex> lock(mutex);
      stop = true;
    }
    wake.notify_all();
    if (thread.joinable()) thread.join();
  }
};

ModbusPoller::ModbusPoller(ModbusPollerConfig config, const RegisterMap& map, std::vector<uint16_t> initial)
    : impl_(std::make_unique<Impl>(std::move(config), map, std::move(initial))) {}

ModbusPoller::~ModbusPoller() { impl_->Shutdown(); }

ModbusPollerCounters ModbusPoller::counters() const {
  ModbusPollerCounters c;
  c.reads_ok = impl_->reads_ok.load();
  c.reads_failed = impl_->reads_failed.load();
  c.connects = impl_->connects.load();
  c.connected = impl_->connected.load();
  return c;
}

Status ModbusPoller::DoStart() {
  Impl& m = *impl_;
  m.Shutdown();
  const RegisterMap& map = m.input.map();
  if (m.config.map.empty()) return Status(StatusCode::kInvalidArgument, "modbus-poller: empty register map");
  m.target.clear();
  int lo = 65535, hi = 0;
  for (const PollEntry& e : m.config.map) {
    int fixture = -1;
    for (int f = 0; f < map.fixture_count(); ++f) {
      if (map.fixture(f).name == e.fixture) fixture = f;
    }
    if (fixture < 0) {
      return Status(StatusCode::kNotFound, "modbus-poller: map entry for register " + std::to_string(e.peer_register) +
                                               ": no fixture '" + e.fixture + "'");
    }
    const int offset = map.fixture(fixture).layout.OffsetOf(e.channel);
    if (offset < 0) {
      return Status(StatusCode::kInvalidArgument, "modbus-poller: map entry for register " +
                                                      std::to_string(e.peer_register) + ": fixture '" + e.fixture +
                                                      "' has no '" + ChannelName(e.channel) + "' register");
    }
    m.target.push_back(map.fixture(fixture).modbus_base + offset);
    lo = e.peer_register < lo ? e.peer_register : lo;
    hi = e.peer_register > hi ? e.peer_register : hi;
  }
  if (hi - lo + 1 > MODBUS_MAX_READ_REGISTERS) {
    return Status(StatusCode::kInvalidArgument, "modbus-poller: mapped registers span more than 125 addresses");
  }
  m.first = lo;
  m.count = hi - lo + 1;
  m.stop = false;
  m.connected.store(false);
  m.thread = std::thread([&m] { m.Run(); });
  return Status::Ok();
}

size_t ModbusPoller::DoPoll(int64_t /*now_us*/, ParamChange* out, size_t capacity) {
  return impl_->input.Collect(out, capacity);
}

void ModbusPoller::DoStop() { impl_->Shutdown(); }

}  // namespace relight::hal
