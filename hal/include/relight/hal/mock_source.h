// Mock backend: the hardware as a test programs it. It decodes what it is
// given exactly as the real backends do — holding registers through the
// register map (with the same checks a Modbus server applies), GPIO lines
// through the same debounce and quadrature decoder — so behaviour tested
// here is the real backends' behaviour minus the wire. It also records what
// the daemon does with it (starts, polls, frames reported).
//
//   MockSource mock(patch);                      // a resolved patch
//   mock.SetHoldingRegister(1, 40000, t_us);     // pan of fixture 0
//   mock.SetLine("gpiochip0", 17, false, t_us);  // a button pressed
//   n = mock.Poll(now_us, out, capacity);
//
// Storage is fixed at construction (kQueueCapacity injected changes; the
// oldest is dropped and counted beyond that). Thread safety: none.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "relight/hal/input_source.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal {

class MockSource final : public InputSource {
 public:
  static constexpr size_t kQueueCapacity = 1024;

  // `patch` resolved (ResolvePatch); `initial` as for the Modbus servers.
  explicit MockSource(const Patch& patch, std::vector<uint16_t> initial = {},
                      SourceClock clock = SourceClock::kMonotonic);
  ~MockSource() override;

  // --- injection (the test's side)
  // A Modbus write as a server would take it: 0 if accepted, else the
  // exception code a server would answer (nothing changes then).
  uint8_t SetHoldingRegister(int addr, uint16_t value, int64_t time_us);
  uint16_t holding_register(int addr) const;
  // A GPIO line's raw level (true = high) at time_us; kNotFound if the patch
  // uses no such line.
  Status SetLine(const std::string& chip, int line, bool level, int64_t time_us);
  // A change delivered as is, when Poll's now_us reaches its time_us.
  void Inject(const ParamChange& change);
  void FailStartWith(Status status);
  void SetFinished(bool finished);

  // --- records
  int start_count() const;
  int stop_count() const;
  int poll_count() const;
  uint32_t frames_reported() const;  // OnFrameOut calls
  uint32_t last_frame() const;
  uint32_t last_latency_us() const;
  size_t dropped() const;  // injected changes lost to a full queue

 private:
  Status DoStart() override;
  size_t DoPoll(int64_t now_us, ParamChange* out, size_t capacity) override;
  bool DoFinished() const override;
  const char* DoName() const override { return "mock"; }
  SourceClock DoClock() const override;
  void DoOnFrameOut(uint32_t frame, uint32_t latency_us) override;
  void DoStop() override;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight::hal
