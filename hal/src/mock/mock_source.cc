#include "relight/hal/mock_source.h"

#include <cstdio>

#include "../change_ring.h"
#include "../gpio_decoder.h"
#include "../register_input.h"

namespace relight::hal {

struct MockSource::Impl {
  RegisterMap map;
  RegisterInput registers;
  GpioDecoder gpio;
  ChangeRing queue{kQueueCapacity};
  SourceClock clock;
  Status start_status;
  bool finished = false;
  int starts = 0, stops = 0, polls = 0;
  uint32_t frames = 0, last_frame = 0, last_latency_us = 0;

  Impl(RegisterMap m, std::vector<uint16_t> initial, const Patch& patch, SourceClock c)
      : map(std::move(m)), registers(map, std::move(initial)), gpio(patch), clock(c) {}
};

namespace {

RegisterMap BuildMap(const Patch& patch) {
  RegisterMap map;
  const Status st = RegisterMap::Build(patch.fixtures, &map);
  // A mock built from an unresolved patch is a test bug, not an input error.
  if (!st.ok()) std::fprintf(stderr, "MockSource: %s\n", st.ToString().c_str());
  RELIGHT_CHECK(st.ok());
  return map;
}

}  // namespace

MockSource::MockSource(const Patch& patch, std::vector<uint16_t> initial, SourceClock clock)
    : impl_(std::make_unique<Impl>(BuildMap(patch), std::move(initial), patch, clock)) {}

MockSource::~MockSource() = default;

uint8_t MockSource::SetHoldingRegister(int addr, uint16_t value, int64_t time_us) {
  if (const uint8_t e = impl_->map.CheckWrite(addr, value); e != 0) return e;
  impl_->registers.Write(addr, 1, &value, time_us);
  return 0;
}

uint16_t MockSource::holding_register(int addr) const {
  const std::vector<uint16_t> regs = impl_->registers.Snapshot();
  return addr >= 0 && static_cast<size_t>(addr) < regs.size() ? regs[static_cast<size_t>(addr)] : 0;
}

Status MockSource::SetLine(const std::string& chip, int line, bool level, int64_t time_us) {
  const int index = impl_->gpio.Find(chip, line);
  if (index < 0) {
    return Status(StatusCode::kNotFound, "mock: the patch uses no line " + std::to_string(line) + " on " + chip);
  }
  impl_->gpio.OnEdge(index, level, time_us, &impl_->queue);
  return Status::Ok();
}

void MockSource::Inject(const ParamChange& change) { impl_->queue.Push(change); }
void MockSource::FailStartWith(Status status) { impl_->start_status = std::move(status); }
void MockSource::SetFinished(bool finished) { impl_->finished = finished; }
int MockSource::start_count() const { return impl_->starts; }
int MockSource::stop_count() const { return impl_->stops; }
int MockSource::poll_count() const { return impl_->polls; }
uint32_t MockSource::frames_reported() const { return impl_->frames; }
uint32_t MockSource::last_frame() const { return impl_->last_frame; }
uint32_t MockSource::last_latency_us() const { return impl_->last_latency_us; }
size_t MockSource::dropped() const { return impl_->queue.dropped(); }

Status MockSource::DoStart() {
  ++impl_->starts;
  return impl_->start_status;
}

size_t MockSource::DoPoll(int64_t now_us, ParamChange* out, size_t capacity) {
  ++impl_->polls;
  impl_->gpio.Tick(now_us, &impl_->queue);
  size_t n = impl_->registers.Collect(out, capacity);
  n += impl_->queue.PopDue(now_us, out + n, capacity - n);
  return n;
}

bool MockSource::DoFinished() const { return impl_->finished; }
SourceClock MockSource::DoClock() const { return impl_->clock; }

void MockSource::DoOnFrameOut(uint32_t frame, uint32_t latency_us) {
  ++impl_->frames;
  impl_->last_frame = frame;
  impl_->last_latency_us = latency_us;
}

void MockSource::DoStop() { ++impl_->stops; }

}  // namespace relight::hal
