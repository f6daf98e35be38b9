// DmxOlaSource: OLA client on its own thread; frames decoded per fixture.
#include "relight/hal/dmx/ola_source.h"

#include <ola/Callback.h>
#include <ola/DmxBuffer.h>
#include <ola/Logging.h>
#include <ola/client/ClientWrapper.h>
#include <ola/client/OlaClient.h>
#include <ola/io/SelectServer.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "dmx_changes.h"
#include "relight/base/clock.h"
#include "relight/base/log.h"

namespace relight::hal {

struct DmxOlaSource::Impl {
  DmxPatch patch;
  DmxOlaConfig config;
  std::vector<unsigned> universes;           // distinct, from the patch

  DmxChanges changes;                         // frames -> values -> changes (locks itself)
  mutable std::mutex mu;                     // guards ss
  ola::io::SelectServer* ss = nullptr;       // the running loop, for Stop()

  std::condition_variable wake;
  std::atomic<bool> stop{false};
  std::atomic<bool> is_connected{false};
  // A registration failed on this connection: it is dropped and made again.
  std::atomic<bool> registration_failed{false};
  std::atomic<uint32_t> frames{0};
  std::unique_ptr<ola::client::OlaClientWrapper> first;  // connected by Start()
  std::thread thread;

  Impl(DmxPatch p, DmxOlaConfig c) : patch(std::move(p)), config(c), changes(patch) {
    for (const DmxFixturePatch& f : patch.fixtures) {
      const auto u = static_cast<unsigned>(f.universe);
      if (std::find(universes.begin(), universes.end(), u) == universes.end()) universes.push_back(u);
    }
  }

  // OLA thread. Frames hold only the data slots (start code 0 implied).
  void OnDmx(const ola::client::DMXMetadata& meta, const ola::DmxBuffer& data) {
    const int64_t now_us = MonotonicUs();
    frames.fetch_add(1, std::memory_order_relaxed);
    changes.OnFrame(meta.universe, data.GetRaw(), data.Size(), now_us);
  }

  // A refused registration leaves the connection deaf to that universe. Most
  // often the channel closed under it (olad going away just as we connected:
  // seen in CI, where the close handler then never ran and the source stayed
  // "connected" to nothing), so the connection is dropped and made again
  // after reconnect_ms rather than kept.
  void OnRegistered(unsigned universe, const ola::client::Result& result) {
    if (result.Success()) return;
    Log(LogLevel::kError, "dmx-ola: olad refused universe %u: %s; connecting again in %d ms", universe,
        result.Error().c_str(), config.reconnect_ms);
    registration_failed.store(true);
  }

  void OnClose() {
    Log(LogLevel::kWarning, "dmx-ola: olad closed the connection; holding the current look, reconnecting");
    std::lock_guard<std::mutex> lock(mu);
    if (ss != nullptr) ss->Terminate();
  }

  // Also ends a connection whose registration failed (the callback may come
  // before the loop runs, so the loop checks the flag itself).
  bool CheckStop() {
    if (stop.load() || registration_failed.load()) {
      std::lock_guard<std::mutex> lock(mu);
      if (ss != nullptr) ss->Terminate();
    }
    return true;  // keep the repeating timeout
  }

  // Registers for the patch's universes and runs the loop until olad goes
  // away or Stop().
  void Serve(ola::client::OlaClientWrapper& wrapper) {
    ola::client::OlaClient* client = wrapper.GetClient();
    client->SetDMXCallback(ola::NewCallback(this, &Impl::OnDmx));
    client->SetCloseHandler(ola::NewSingleCallback(this, &Impl::OnClose));
    for (const unsigned u : universes) {
      client->RegisterUniverse(u, ola::client::REGISTER, ola::NewSingleCallback(this, &Impl::OnRegistered, u));
    }
    ola::io::SelectServer* loop = wrapper.GetSelectServer();
    // Stop() may come before Run() starts: the loop checks the flag itself.
    loop->RegisterRepeatingTimeout(100, ola::NewCallback(this, &Impl::CheckStop));
    {
      std::lock_guard<std::mutex> lock(mu);
      ss = loop;
    }
    is_connected.store(true);
    loop->Run();
    is_connected.store(false);
    std::lock_guard<std::mutex> lock(mu);
    ss = nullptr;
  }

  void Run() {
    std::unique_ptr<ola::client::OlaClientWrapper> wrapper = std::move(first);
    bool announced = false;
    while (!stop.load()) {
      if (wrapper == nullptr) {
        wrapper = std::make_unique<ola::client::OlaClientWrapper>(false);
        if (!wrapper->Setup()) {
          wrapper.reset();
          if (!announced) Log(LogLevel::kWarning, "dmx-ola: olad not reachable; retrying every %d ms", config.reconnect_ms);
          announced = true;
          std::unique_lock<std::mutex> lock(mu);
          wake.wait_for(lock, std::chrono::milliseconds(config.reconnect_ms), [&] { return stop.load(); });
          continue;
        }
        Log(LogLevel::kInfo, "dmx-ola: connected to olad");
        announced = false;
      }
      Serve(*wrapper);
      wrapper.reset();
      if (registration_failed.exchange(false)) {
        std::unique_lock<std::mutex> lock(mu);
        wake.wait_for(lock, std::chrono::milliseconds(config.reconnect_ms), [&] { return stop.load(); });
      }
    }
  }
};

DmxOlaSource::DmxOlaSource(DmxPatch patch, DmxOlaConfig config)
    : impl_(std::make_unique<Impl>(std::move(patch), config)) {}

DmxOlaSource::~DmxOlaSource() { DoStop(); }

Status DmxOlaSource::DoStart() {
  if (impl_->thread.joinable()) return Status(StatusCode::kInvalidArgument, "dmx-ola: already started");
  if (impl_->patch.fixtures.empty()) return Status(StatusCode::kInvalidArgument, "dmx-ola: the DMX patch has no fixtures");
  static std::once_flag logging;
  std::call_once(logging, [] { ola::InitLogging(ola::OLA_LOG_WARN, ola::OLA_LOG_STDERR); });
  auto wrapper = std::make_unique<ola::client::OlaClientWrapper>(false);  // never auto-start olad
  if (!wrapper->Setup()) {
    const char* why =
        "dmx-ola: olad is not running (nothing answers on 127.0.0.1:9010); start it as a non-root user, "
        "e.g. `olad -c ~/.ola --no-http`, and enable its E1.31 or Art-Net plugin (docs/dmx.md)";
    if (!impl_->config.wait_for_olad) return Status(StatusCode::kIoError, why);
    Log(LogLevel::kWarning, "%s; retrying every %d ms, the bake's look stays meanwhile", why,
        impl_->config.reconnect_ms);
    wrapper.reset();
  }
  impl_->stop.store(false);
  impl_->first = std::move(wrapper);
  impl_->thread = std::thread([this] { impl_->Run(); });
  return Status::Ok();
}

size_t DmxOlaSource::DoPoll(int64_t now_us, ParamChange* out, size_t capacity) {
  return impl_->changes.Collect(now_us, out, capacity);
}

void DmxOlaSource::DoStop() {
  if (!impl_->thread.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(impl_->mu);
    impl_->stop.store(true);
    if (impl_->ss != nullptr) impl_->ss->Terminate();
  }
  impl_->wake.notify_all();
  impl_->thread.join();
}

bool DmxOlaSource::LatestValues(size_t index, int64_t now_us, DmxFixtureValues* out) const {
  return impl_->changes.LatestValues(index, now_us, out);
}

bool DmxOlaSource::connected() const { return impl_->is_connected.load(); }
uint32_t DmxOlaSource::frames_received() const { return impl_->frames.load(); }

}  // namespace relight::hal
